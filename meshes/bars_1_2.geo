// The two bars of bars.geo with the right-hand one 2L long (docs/bodies.md: the short bar striking the long one).
DefineConstant[ L2 = 20 ];
Include "bars.geo";
