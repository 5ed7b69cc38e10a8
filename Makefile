# The two commands of the README. Each installs what it needs first (scripts/setup.sh).
.PHONY: setup demo test
export LANG := C.UTF-8

setup:
	@bash scripts/setup.sh

# The main job: interpret a bundled sketch session (strokes drawn over the model, step by
# step) into a protocol, a STEP file and a picture; then build the example protocols.
demo: setup
	.venv/bin/sketch2cad interpret examples/sessions/camera.json --keep-going \
	    --protocol out/camera-interpreted.json --step out/camera-interpreted.step \
	    --png out/camera-interpreted.png
	.venv/bin/sketch2cad demo --out out

# The whole test suite, FreeCAD and GUI tests included.
test: setup
	bash scripts/run_tests.sh
