# The two commands of the README. Each installs what it needs first (scripts/setup.sh).
.PHONY: setup demo test
export LANG := C.UTF-8

setup:
	@bash scripts/setup.sh

# The main job: build the bundled example protocols into STEP files and pictures under out/.
demo: setup
	.venv/bin/sketch2cad demo --out out

# The whole test suite, FreeCAD and GUI tests included.
test: setup
	bash scripts/run_tests.sh
