# The two commands of the README. Each installs what it needs first (scripts/setup.sh).
.PHONY: setup demo test weights head5
export LANG := C.UTF-8

setup:
	@bash scripts/setup.sh

# The main job: interpret a bundled sketch session (strokes drawn over the model, step by
# step) into a protocol, a STEP file and a picture; then build the example protocols.
demo: setup
	.bin/sketch2cad interpret examples/sessions/camera.json --keep-going \
	    --protocol out/camera-interpreted.json --step out/camera-interpreted.step \
	    --png out/camera-interpreted.png
	.bin/sketch2cad demo --out out

# The whole test suite, FreeCAD and GUI tests included.
test: setup
	bash scripts/run_tests.sh

# Not part of demo or test: the shipped weights from scratch (data, 90 min of
# training on 2 CPU cores, evaluation, model card), then the structured head on the
# U-Net's frozen features, trained on planar samples and samples on curved faces (the
# planar set ~13 min and the curved set ~6 min on 2 cores; tokens once, ~6 min; the
# head ~16 min; the ablation without context ~2 min), both scored beside the U-Net and
# end to end (model card); last, `head5` fine-tunes that head into the shipped one.
# Each step resumes where it stopped.
weights: setup
	.bin/sketch2cad datagen --out data/train2 --count 20000 --seed 1 --noise-level mix
	for n in 1 2 3; do \
	    .bin/sketch2cad datagen --out data/test-l$$n --count 400 --seed 1000$$n \
	        --noise-level $$n || exit 1; done
	.bin/sketch2cad train --data data/train2 --out runs/main --minutes 90 --threads 2
	for n in 1 2 3; do \
	    .bin/sketch2cad eval --data data/test-l$$n --weights runs/main \
	        --json runs/eval-l$$n.json --report docs/eval-l$$n.png --recovery 400 \
	        --fitting-recovery || exit 1; done
	.bin/sketch2cad datagen --out data/head-train --count 27648 --seed 1 --noise-level mix
	.bin/sketch2cad datagen --curved --out data/curved-train --count 1536 --seed 2 \
	    --noise-level mix
	.bin/sketch2cad datagen --curved --out data/curved-50003 --count 100 --seed 50003 \
	    --noise-level 1
	for n in 1 3; do \
	    .bin/sketch2cad datagen --out data/head-test-l$$n --count 400 --seed 4000$$n \
	        --noise-level $$n || exit 1; \
	    .bin/sketch2cad datagen --out data/heldout-l$$n --count 200 --seed 3000$$n \
	        --noise-level $$n || exit 1; done
	.bin/sketch2cad train-head --data data/head-train data/curved-train \
	    --out runs/head --epochs 20 --width 128 --tokens runs/head-tokens --weights runs/main \
	    --eval data/head-test-l1 data/head-test-l3 data/curved-50003 \
	    --json runs/head/scores.json
	.bin/sketch2cad train-head --data data/head-train data/curved-train \
	    --out runs/head-noctx --epochs 20 --width 128 --layers 0 --tokens runs/head-tokens \
	    --weights runs/main \
	    --eval data/head-test-l1 data/head-test-l3 data/curved-50003 \
	    --json runs/head-noctx/scores.json
	for n in 1 3; do \
	    .bin/sketch2cad head-recovery --data data/heldout-l$$n --head runs/head \
	        --weights runs/main --limit 200 --json runs/head-recovery/heldout-l$$n.json \
	        || exit 1; done
	.bin/sketch2cad model-card --run runs/main \
	    --eval 1=runs/eval-l1.json 2=runs/eval-l2.json 3=runs/eval-l3.json \
	    --heads runs/head/scores.json runs/head-noctx/scores.json \
	    --head-recovery runs/head-recovery/heldout-l1.json runs/head-recovery/heldout-l3.json \
	    --ship-head
	$(MAKE) head5

# The shipped head: the head above fine-tuned into five classes (the shell learnt) on
# shells, rounds, people's hand and the generator's (~30 min of data, most of it the
# shells' offsets; ~5 min of tokens and ~4 min of training on 2 cores), scored on
# held-out sets of both hands and shipped with its figures (model card).
head5: setup
	.bin/sketch2cad datagen --out data/head-train-8k --count 8192 --seed 1 --noise-level mix
	.bin/sketch2cad datagen --out data/head-train5 --count 2048 --seed 1 --noise-level mix \
	    --shells --round-share 0.25
	.bin/sketch2cad datagen --out data/people-train --count 4096 --seed 3 --noise-level mix \
	    --round-share 0.25 --hand people
	.bin/sketch2cad datagen --curved --out data/curved-train5 --count 512 --seed 2 \
	    --noise-level mix
	for n in 1 3; do \
	    .bin/sketch2cad datagen --out data/heldout5-l$$n --count 300 --seed 3110$$n \
	        --noise-level $$n --shells --round-share 0.25 || exit 1; \
	    .bin/sketch2cad datagen --out data/people-l$$n --count 200 --seed 3120$$n \
	        --noise-level $$n --hand people || exit 1; done
	.bin/sketch2cad train-head --data data/head-train-8k data/head-train5 data/people-train \
	    data/curved-train5 --out runs/head5 --init runs/head/sketch2cad_head.pt --epochs 10 \
	    --width 128 --lr 2e-4 --threads 2 --weights runs/main --eval data/heldout5-l1 \
	    data/heldout5-l3 data/people-l1 data/people-l3 --json runs/head5/scores.json
	.bin/sketch2cad model-card --tuned runs/head5/scores.json
