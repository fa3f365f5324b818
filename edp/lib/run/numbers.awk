# run/numbers.awk -- what body/check_mesh.awk and io/check_checkpoint.awk take as numbers.
function isnum(s) { return s ~ /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/ }
function isint(s) { return s ~ /^[0-9]+$/ }
# a number that FreeFEM reads as a finite double
function isfinite(s) { return isnum(s) && s + 0 < 1e300 && s + 0 > -1e300 }
