# FreeFEM suite for impact/contact of an elastic disk on a moving foundation
# (Murea 2023). `make` reproduces the paper's figures; `make check` runs the tests.
# See README.md.

SHELL := /bin/bash
PYTHON ?= /usr/bin/python3
RESULTS ?= results
FIGURES ?= $(RESULTS)/figures
SCENE ?= test1
# make run writes here by default: a directory no other target owns
OUT ?= $(RESULTS)/runs/$(SCENE)
ARGS ?=
# runs at a time in make svk, methods, csm3 and hertz (the machine has 2 cores); a positive integer, checked when one
# of them is a goal, before anything is built or removed: one line naming JOBS (make's `*** ... Stop.`, exit 2)
JOBS ?= 2
ifneq ($(filter svk methods csm3 hertz,$(MAKECMDGOALS)),)
JOBS_NOT_DIGITS := $(subst 9,,$(subst 8,,$(subst 7,,$(subst 6,,$(subst 5,,$(subst 4,,$(subst 3,,$(subst 2,,$(subst 1,,$(subst 0,,$(JOBS)))))))))))
ifneq ($(strip $(words $(JOBS)) $(JOBS_NOT_DIGITS) $(if $(subst 0,,$(strip $(JOBS))),positive)),1 positive)
$(error JOBS must be a positive integer (runs at a time of make svk, methods, csm3 and hertz), got '$(JOBS)')
endif
endif
# processes of each run in make run, ball, accuracy, stress, svk, methods, csm3, hertz and sliding (NP=N: edp/run.sh -np N); when
# given, to any goal, what run.sh -np takes (1 to 1024, at most 4 digits), checked like JOBS before anything is built
# or removed (a goal that does not use it says so below, but a value it could never take is refused all the same)
ifneq ($(filter command line environment%,$(origin NP)),)
ifneq ($(NP),)
ifneq ($(shell n='$(subst ','\'',$(NP))'; [[ $$n =~ ^[0-9]{1,4}$$ ]] && (( 10#$$n >= 1 && 10#$$n <= 1024 )) && echo ok),ok)
$(error NP must be a whole number of processes per run from 1 to 1024 (edp/run.sh -np N), got '$(NP)')
endif
endif
endif
T1_VALUES := 18 22 26
# NP=N (each run on N processes, docs/parallel.md) and JOBS=N (runs at a time): a goal that does not use one that
# is given says so in one line, with why, and runs as it would without it
NP_GIVEN := $(filter command line environment%,$(origin NP))
JOBS_GIVEN := $(filter command line environment%,$(origin JOBS))
GOALS := $(or $(MAKECMDGOALS),all)
ifneq ($(NP_GIVEN),)
$(foreach g,$(filter test1 test2 paper all figures,$(GOALS)),$(info note: make $(g) runs serially: the paper's runs use -solver ipopt, which does not run on -np (docs/parallel.md); NP=$(NP) is not used))
$(foreach g,$(filter bench,$(GOALS)),$(info note: make bench runs its cases serially and on 1, 2 and 4 processes itself (docs/parallel.md); NP=$(NP) is not used))
$(foreach g,$(filter friction,$(GOALS)),$(info note: make friction runs its cases serially: every one has -friction, which does not run on -np (docs/parallel.md); NP=$(NP) is not used))
$(foreach g,$(filter hostile,$(GOALS)),$(info note: make hostile runs its cases as it draws them, -np among their options; NP=$(NP) is not used))
$(foreach g,$(filter animation check,$(GOALS)),$(info note: make $(g) starts no run of its own; NP=$(NP) is not used))
endif
ifneq ($(JOBS_GIVEN),)
$(foreach g,$(filter accuracy stress bench,$(GOALS)),$(info note: make $(g) times its runs, so it runs them one at a time; JOBS=$(JOBS) is not used))
$(foreach g,$(filter test1 test2 ball paper all figures,$(GOALS)),$(info note: make $(g)'s runs are make's own rules: make -j $(JOBS) $(g) runs $(JOBS) at a time; JOBS=$(JOBS) is not used))
$(foreach g,$(filter run animation check hostile,$(GOALS)),$(info note: make $(g) runs one thing at a time; JOBS=$(JOBS) is not used))
endif

EDP_SOURCES := edp/contact.edp edp/run.sh $(wildcard edp/lib/*/*.idp edp/lib/*/*.awk edp/lib/*/*.sh edp/lib/*/*.txt edp/lib/*/*.opt)
RUN := edp/run.sh
# every meshes/NAME.geo gives meshes/NAME.msh (refine 1); the disk also a coarser and a finer one, the Hertz ball a coarser one
MESHES := $(patsubst %.geo,%.msh,$(wildcard meshes/*.geo)) meshes/disk_coarse.msh meshes/disk_fine.msh meshes/hertz_coarse.msh meshes/two_disks_coarse.msh meshes/cradle_coarse.msh meshes/patch_fine.msh

.PHONY: all paper plugins deps deps-packages deps-run deps-plot deps-test meshes run animation test1 test2 figures ball check hostile same-results bench bench-one-body accuracy stress svk csm3 hertz methods friction sliding bodies scenes clean
.DELETE_ON_ERROR:

all: paper
paper: test1 test2 figures $(FIGURES)/bounce.gif
	@echo "figures: $(FIGURES)/ (fig1..fig7, PNG and PDF; bounce.gif)"

# ---- dependencies (Debian packages; see ../shared/notes/freefem-on-debian.md), in
# three sets: running (deps-run), plotting (deps-plot), testing (deps-test).
# Installed with apt-get as root; otherwise the command is printed and make stops.
# The BLAS is OpenBLAS (pthreads), which Debian then selects for CHOLMOD: every time in docs/ was measured with
# it, and the reference BLAS (libblas3, which FreeFEM alone pulls in) is several times slower and rounds otherwise.
define install_missing
	@missing=""; $(1) \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ]; then \
	    echo "installing:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing >/dev/null; \
	  else \
	    echo "missing:$$missing"; echo "run as root:  apt-get update && apt-get install -y$$missing"; exit 1; \
	  fi; \
	fi
endef
# The serial solves' plugin (edp/lib/solve/cholmod_columns.cpp: CHOLMOD's factor with its halves apart), built
# with FreeFEM's ff-c++ into build/plugins/, where edp/run.sh loads it from
PLUGIN = build/plugins/cholmod_columns.so
# and the contact between bodies' (edp/lib/contact/body_contact.cpp: the dual mortar rows, the search)
BODY_PLUGIN = build/plugins/body_contact.so
# and the studies' launcher (postprocess/peak_rss.cpp: a run's peak memory, not the forking Python's)
PEAK_RSS = build/peak_rss
deps-run: $(PLUGIN) $(BODY_PLUGIN) $(PEAK_RSS)
$(PEAK_RSS): postprocess/peak_rss.cpp | deps-packages
	@mkdir -p build
	@g++ -O2 -Wall -o $@ $<
deps-packages:
	$(call install_missing, \
	command -v FreeFem++-nw >/dev/null || missing="$$missing freefem++"; \
	[ -f /usr/lib/freefem++/ff-Ipopt.so ] || missing="$$missing libfreefem++"; \
	[ -f /usr/include/freefem++/idp/getARGV.idp ] || missing="$$missing libfreefem++-dev"; \
	command -v gmsh >/dev/null || missing="$$missing gmsh"; \
	command -v flock >/dev/null || missing="$$missing util-linux"; \
	command -v g++ >/dev/null || missing="$$missing g++"; \
	[ -f /usr/include/suitesparse/cholmod.h ] || missing="$$missing libsuitesparse-dev"; \
	ls /usr/lib/*/openblas-pthread/libblas.so.3 >/dev/null 2>&1 || missing="$$missing libopenblas0-pthread"; \
	[ -x $(PYTHON) ] || missing="$$missing python3";)
plugins: $(PLUGIN) $(BODY_PLUGIN)
$(PLUGIN): edp/lib/solve/cholmod_columns.cpp edp/lib/solve/memory_left.hpp edp/lib/solve/cholmod_arrays.hpp | deps-packages
	@mkdir -p build/plugins
	@echo "building $@ (ff-c++) ..."
	@cd build/plugins && cp ../../edp/lib/solve/cholmod_columns.cpp ../../edp/lib/solve/*.hpp . && \
	  if ff-c++ cholmod_columns.cpp -lcholmod > build.log 2>&1; then rm -f cholmod_columns.cpp *.hpp cholmod_columns.o; \
	  else grep -i -m 5 "error" build.log; echo "$@: ff-c++ failed (build/plugins/build.log)"; rm -f cholmod_columns.so; exit 1; fi
$(BODY_PLUGIN): edp/lib/contact/body_contact.cpp | deps-packages
	@mkdir -p build/plugins
	@echo "building $@ (ff-c++) ..."
	@cd build/plugins && cp ../../edp/lib/contact/body_contact.cpp . && \
	  if ff-c++ body_contact.cpp > build_body.log 2>&1; then rm -f body_contact.cpp body_contact.o; \
	  else grep -i -m 5 "error" build_body.log; echo "$@: ff-c++ failed (build/plugins/build_body.log)"; rm -f body_contact.so; exit 1; fi
deps-plot: deps-run
	$(call install_missing, \
	$(PYTHON) -c 'import numpy' 2>/dev/null || missing="$$missing python3-numpy"; \
	$(PYTHON) -c 'import matplotlib' 2>/dev/null || missing="$$missing python3-matplotlib"; \
	$(PYTHON) -c 'import meshio' 2>/dev/null || missing="$$missing python3-meshio";)
deps-test: deps-plot
	$(call install_missing, \
	$(PYTHON) -c 'import pytest' 2>/dev/null || missing="$$missing python3-pytest"; \
	$(PYTHON) -c 'import hypothesis' 2>/dev/null || missing="$$missing python3-hypothesis"; \
	$(PYTHON) -c 'import xdist' 2>/dev/null || missing="$$missing python3-pytest-xdist"; \
	command -v mpirun >/dev/null || missing="$$missing openmpi-bin";)
deps: deps-test

# ---- meshes: meshes/NAME.msh from meshes/NAME.geo (gmsh, MSH 2.2, -setnumber refine);
# NAME_coarse, NAME_fine, NAME_refine4, NAME_refine6, NAME_refine8: refine 0.5, 2, 4, 6, 8 (the paper's disk,
# refine 1, has 989 vertices; refine 8 about 57,000). A .geo whose first line is `// dimension 3`,
# or that has a Physical Volume, is meshed with gmsh -3 (tetrahedra: a 3D body, docs/3d.md),
# every other one with gmsh -2.
meshes: $(MESHES)
REFINE = 1
meshes/%_coarse.msh: REFINE = 0.5
meshes/%_fine.msh: REFINE = 2
meshes/%_refine4.msh: REFINE = 4
meshes/%_refine6.msh: REFINE = 6
meshes/%_refine8.msh: REFINE = 8
# the Hertz ball (hertz.geo includes ball.geo): its coarse variant, for tests and make hertz's second
# mesh, is refine 0.3 (534 vertices)
meshes/hertz_coarse.msh: REFINE = 0.3
meshes/hertz.msh meshes/hertz_coarse.msh: meshes/ball.geo
meshes/bars_1_2.msh: meshes/bars.geo
# make bench's middle ball (docs/bench.md): refine 2.45, 6907 vertices, the size of issue 25's scipy reference
meshes/ball_medium.msh: REFINE = 2.45
meshes/ball_medium.msh: meshes/ball.geo | deps-run
	$(build_mesh)
# One line while gmsh works (and every 30 s on a long build), one line on a gmsh error (its first
# "Error" line; the whole log stays in $@.log).
define build_mesh
	@echo "meshing $@ from $< (refine $(REFINE)) ..."
	@dimension=2; { [ "$$(head -n 1 $<)" = "// dimension 3" ] || grep -q 'Physical Volume' $<; } && dimension=3; \
	gmsh -$$dimension -format msh22 -nt 1 -setnumber refine $(REFINE) $< -o $@ > $@.log 2>&1 & pid=$$!; waited=0; \
	trap 'kill $$pid 2>/dev/null; rm -f $@ $@.log; exit 130' INT TERM; \
	while kill -0 $$pid 2>/dev/null; do sleep 1; waited=$$((waited + 1)); \
	  [ $$((waited % 30)) = 0 ] && echo "meshing $@: $$waited s ..."; done; \
	if ! wait $$pid || [ ! -s $@ ]; then \
	  echo "error: gmsh could not mesh $<: $$(grep -m 1 -i 'error' $@.log || tail -n 1 $@.log) (whole log: $@.log)" >&2; \
	  rm -f $@; exit 1; fi
	@rm -f $@.log
	@$(PYTHON) postprocess/mesh_counts.py $@
endef
meshes/%.msh: meshes/%.geo | deps-run
	$(build_mesh)
meshes/%_coarse.msh: meshes/%.geo | deps-run
	$(build_mesh)
meshes/%_fine.msh: meshes/%.geo | deps-run
	$(build_mesh)
meshes/%_refine4.msh: meshes/%.geo | deps-run
	$(build_mesh)
meshes/%_refine6.msh: meshes/%.geo | deps-run
	$(build_mesh)
meshes/%_refine8.msh: meshes/%.geo | deps-run
	$(build_mesh)

# ---- one simulation: make run SCENE=<name> OUT=<dir> ARGS="-key value ..." [NP=N: on N processes, docs/parallel.md]
# Its prerequisite is the mesh the run uses (-mesh in ARGS, else the scene's meshFile, else the disk) when it is a
# meshes/NAME.msh that a rule above makes (its .geo exists); a broken .geo elsewhere in meshes/ does not matter, and
# any other -mesh is run.sh's to check. A prerequisite, not a make called from the recipe: a mesh that gmsh cannot
# build is its one error line and make's, and a refused run is the run's one error line and make's `Error N`
# (docs/errors.md, "Through make"); the recipe is not echoed.
ifneq ($(filter run,$(MAKECMDGOALS)),)
RUN_SCENE_FILE := $(if $(findstring /,$(SCENE))$(filter %.idp,$(SCENE)),$(SCENE),edp/scenes/$(SCENE).idp)
RUN_MESH := $(shell mesh=meshes/disk.msh; \
  scene_mesh=$$(sed -n 's/^[[:space:]]*meshFile[[:space:]]*=[[:space:]]*"\([^"]*\)".*/\1/p' '$(RUN_SCENE_FILE)' 2>/dev/null | tail -n 1); \
  [ -n "$$scene_mesh" ] && mesh=$$scene_mesh; \
  set -- $(ARGS); while [ $$# -gt 1 ]; do [ "$$1" = -mesh ] && mesh=$$2; shift; done; \
  case "$$mesh" in (./*) mesh=$${mesh:2} ;; esac; \
  case "$$mesh" in (*[!A-Za-z0-9_./-]*) ;; (meshes/*.msh) echo "$$mesh" ;; esac)
# its .geo: meshes/NAME.geo for meshes/NAME.msh and for meshes/NAME_{coarse,fine,medium,refine4,refine6,refine8}.msh
RUN_MESH_GEO := $(wildcard $(patsubst %.msh,%.geo,$(RUN_MESH)) \
  $(foreach s,_coarse _fine _medium _refine4 _refine6 _refine8,$(patsubst %$(s).msh,%.geo,$(filter %$(s).msh,$(RUN_MESH)))))
endif
run: $(if $(RUN_MESH_GEO),$(RUN_MESH)) | deps-run
	@$(RUN) "$(SCENE)" "$(OUT)" $(if $(NP),-np "$(NP)") $(ARGS)

# ---- an animation of a run: make animation OUT=<dir> writes <dir>/animation.gif, and animation.mp4 when
# ffmpeg is on PATH (postprocess/animate.py; the run needs snapshots, e.g. ARGS="-snapshots every:0.25").
# OUT must be given: without it, one line and make's `Stop.` (exit 2), before anything is built.
ifneq ($(filter animation,$(MAKECMDGOALS)),)
ifeq ($(if $(filter file,$(origin OUT)),,$(strip $(OUT))),)
$(error make animation needs OUT=DIR, the run to animate (a directory with run.pvd), e.g. make animation OUT=$(RESULTS)/runs/test1)
endif
endif
animation: | deps-plot
	@$(PYTHON) postprocess/animate.py --run "$(OUT)" --mp4

# ---- the paper's tests (results are rebuilt when the code or scene changes).
# summary.txt is written last, so a killed run is never taken as up to date.
test1: $(RESULTS)/test1/summary.txt
test2: $(RESULTS)/test1/summary.txt $(foreach t1,$(T1_VALUES),$(RESULTS)/test2_t1_$(t1)/summary.txt)

$(RESULTS)/test1/summary.txt: edp/scenes/test1.idp $(EDP_SOURCES) meshes/disk.msh | deps-run
	FORCE=1 $(RUN) test1 $(@D)
$(RESULTS)/test2_t1_%/summary.txt: edp/scenes/test2.idp $(EDP_SOURCES) meshes/disk.msh | deps-run
	FORCE=1 $(RUN) test2 $(@D) -t1 $*

# Test 1's first bounce as an animation: the fall, the impact (t = 8.95 to 23.95) and the rebound to its peak (t = 31.1)
$(RESULTS)/bounce/summary.txt: edp/scenes/test1.idp $(EDP_SOURCES) meshes/disk.msh | deps-run
	FORCE=1 $(RUN) test1 $(@D) -T 32 -snapshots every:0.5
$(FIGURES)/bounce.gif: $(RESULTS)/bounce/summary.txt postprocess/animate.py | deps-plot
	@mkdir -p $(@D)
	$(PYTHON) postprocess/animate.py --run $(<D) --out $@ --fps 8

# ---- the ball (docs/3d.md): Test 1 and Test 2 (t1 = 18, 22, 26) in 3D, and the analogues of Figs. 1-3, 5-6
# (NP=N: each run on N processes)
ball: $(RESULTS)/ball/summary.txt $(foreach t1,$(T1_VALUES),$(RESULTS)/ball_moving_t1_$(t1)/summary.txt) | deps-plot
	$(PYTHON) postprocess/plot_ball.py --results $(RESULTS) --out $(FIGURES)
# (the exact active set: IPOPT takes 307 s CPU for the ball to T = 120, the active set 8.9 s, docs/3d.md)
$(RESULTS)/ball/summary.txt: edp/scenes/ball.idp $(EDP_SOURCES) meshes/ball.msh | deps-run
	FORCE=1 $(RUN) ball $(@D) -solver activeset$(if $(NP), -np "$(NP)")
$(RESULTS)/ball_moving_t1_%/summary.txt: edp/scenes/ball_moving.idp $(EDP_SOURCES) meshes/ball.msh | deps-run
	FORCE=1 $(RUN) ball_moving $(@D) -t1 $* -snapshots none -solver activeset$(if $(NP), -np "$(NP)")

figures: test1 test2 | deps-plot
	$(PYTHON) postprocess/plot_paper.py --results $(RESULTS) --reference tests/reference/getfem-verlet-nitsche-test1.csv --out $(FIGURES)

# ---- tests
# two test files at a time (pytest-xdist, CHECK_JOBS workers, each file whole on one worker; the shared runs of
# tests/conftest.py made once, shared by the workers)
CHECK_JOBS ?= 2
check: meshes | deps-test
	$(PYTHON) -m pytest -q -n $(CHECK_JOBS) --dist loadfile --durations=15 tests

# the hostile test with fresh seeds for MINUTES (30) (tests/hostile.py, docs/tests.md): it prints the shrunk
# counterexamples of any case that breaks the suite's contract
MINUTES ?= 30
hostile: meshes | deps-test
	$(PYTHON) tests/hostile.py --minutes $(MINUTES)

# a change that must move no number (a refactor): 23 representative runs byte-identical to REV (default HEAD)
same-results: meshes | deps-run
	tests/same_results.sh $(REV)

# ---- cost, measured side by side in one run (see postprocess/bench.py)
bench: meshes meshes/disk_refine4.msh meshes/disk_refine8.msh meshes/ball_medium.msh meshes/ball_refine4.msh \
       meshes/ball_refine6.msh | deps-plot
	$(PYTHON) postprocess/bench.py --out $(RESULTS)/bench $(BENCH_ARGS)

# ---- a mesh of one body against the driver before bodies (b78442c^), side by side (postprocess/bench_one_body.py)
bench-one-body: meshes | deps-plot
	$(PYTHON) postprocess/bench_one_body.py --out $(RESULTS)/bench

# ---- what accuracy costs in time (work-precision study; see postprocess/accuracy.py)
accuracy: meshes meshes/disk_refine4.msh meshes/disk_refine8.msh | deps-plot
	$(PYTHON) postprocess/accuracy.py --out $(RESULTS)/accuracy $(if $(NP),--np $(NP))

# ---- hard cases with their criteria (see postprocess/stress.py); results/stress/summary.md
stress: meshes meshes/disk_refine4.msh | deps-plot
	$(PYTHON) postprocess/stress.py --out $(RESULTS)/stress $(if $(NP),--np $(NP))

# ---- linear, St Venant-Kirchhoff and Neo-Hookean bodies side by side (postprocess/svk_compare.py); results/svk/summary.md
svk: meshes | deps-plot
	$(PYTHON) postprocess/svk_compare.py --out $(RESULTS)/svk --jobs $(JOBS) $(if $(NP),--np $(NP))

# ---- the methods of the paper's references beside its own: penalty, Nitsche, singular and lumped mass,
# Newmark, explicit Verlet (see postprocess/methods.py); results/methods/summary.md
methods: meshes | deps-plot
	$(PYTHON) postprocess/methods.py --out $(RESULTS)/methods --jobs $(JOBS) $(if $(NP),--np $(NP))

# ---- the Turek-Hron CSM3 benchmark against its published values, with its convergence in
# mesh, dt and order (see postprocess/csm3.py); results/csm3/summary.md
csm3: meshes meshes/csm3_coarse.msh meshes/csm3_fine.msh | deps-plot
	$(PYTHON) postprocess/csm3.py --out $(RESULTS)/csm3 --jobs $(JOBS) $(if $(NP),--np $(NP))

# ---- the 3D ball's impact on a rigid flat against Hertz's theory, at three speeds, two meshes and two dt
# (issue 25; see postprocess/hertz.py, docs/hertz.md); results/hertz/summary.md
hertz: meshes/hertz.msh meshes/hertz_coarse.msh | deps-plot
	$(PYTHON) postprocess/hertz.py --out $(RESULTS)/hertz --jobs $(JOBS) $(if $(NP),--np $(NP))

# ---- friction's closed-form rigid-body benchmarks (postprocess/friction.py, docs/friction.md); results/friction/summary.md
friction: meshes meshes/hertz_coarse.msh | deps-plot
	$(PYTHON) postprocess/friction.py --out $(RESULTS)/friction --jobs $(JOBS)

# ---- the exact gap against the bowl's closed-form periods, and (10)'s error on the paper's tests
# (postprocess/sliding.py, docs/sliding.md); results/sliding/summary.md
sliding: meshes | deps-plot
	$(PYTHON) postprocess/sliding.py --out $(RESULTS)/sliding --jobs $(JOBS) $(if $(NP),--np $(NP))

# ---- bodies that hit bodies against their closed forms (postprocess/bodies.py, docs/bodies.md); results/bodies/summary.md
bodies: meshes meshes/bars_fine.msh meshes/cradle_coarse.msh meshes/patch_fine.msh | deps-plot
	$(PYTHON) postprocess/bodies.py --out $(RESULTS)/bodies --jobs $(JOBS)

# ---- every scene with the first line of its comment
scenes:
	@for f in edp/scenes/*.idp; do printf '%-12s %s\n' "$$(basename $$f .idp)" "$$(head -1 $$f | sed 's|^// *||')"; done

clean:
	rm -rf $(RESULTS) meshes/*.msh build tests/__pycache__ .pytest_cache .hypothesis
