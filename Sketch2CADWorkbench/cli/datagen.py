# SPDX-License-Identifier: LGPL-2.1-or-later
"""Random modeling sequences rendered as sketches over their context, with labels (paper,
'Training data generation'): a data set deterministic per seed for any worker count, and
resumable (datagen/parallel.py).

`sketch2cad datagen --out DIR --count N [--seed S] [--noise-level 1|2|3|mix]
[--hidden-lines draw|omit|mix] [--regular-share P] [--workers W] [--ray [ADDRESS]]`: with
--ray, one Ray task per shard (datagen/cluster.py), on a local cluster of W CPUs or on the
cluster at ADDRESS. `--regular-share P`: that share of the operations take a designer's
regular parameters (datagen/regular.py). `--shells`: last operations may be shells
(operator 'shell': the rim strokes labelled 1, a line down a wall 0), as often as sweeps;
without it a set is the same as one made before shells.
`--curved`: a set whose operations stand on curved faces (datagen/curved.py): held out,
or the curved part of the head's training data.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from datagen.generate import PER_CONTEXT
from datagen.hand import HANDS
from datagen.parallel import (
    HIDDEN_CHOICES,
    NOISE_CHOICES,
    SHARD_SIZE,
    DatagenSettings,
    generate_dataset,
)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, required=True, help="data set folder")
    p.add_argument("--count", type=int, required=True, help="number of samples")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument(
        "--noise-level",
        default="1",
        choices=NOISE_CHOICES,
        help="stroke noise: 1.4%%, 2.8%%, 4.1%% of the image diagonal (levels 1, "
        "2, 3), or mix (the levels take turns per context); default 1",
    )
    p.add_argument(
        "--hidden-lines",
        default="draw",
        choices=HIDDEN_CHOICES,
        help="draw the lines the view hides (the paper's sketches), leave them out "
        "as a designer drawing what is seen does, or mix (they take turns per "
        "context); default draw",
    )
    p.add_argument(
        "--regular-share",
        type=float,
        default=0.0,
        metavar="P",
        help="share (0 to 1) of the operations drawn with a designer's regular "
        "parameters: lengths on a 1 mm grid or equal to earlier ones, "
        "features centred or on centre lines or concentric, outlines "
        "aligned with the face's edges (datagen/regular.py); default 0",
    )
    p.add_argument(
        "--hand",
        default="generator",
        choices=HANDS,
        help="who draws the strokes: the generator (one whole stroke per curve, "
        "Gaussian end noise: the paper's sketches) or people (outlines in one "
        "stroke, curves split and traced over, stopping short, loops left open, "
        "hidden lines often left out: datagen/hand.py), or people with one of those "
        "habits alone (people-chain, people-split, people-partial, people-hidden, "
        "people-wobble: what each costs); default generator",
    )
    p.add_argument(
        "--shells",
        action="store_true",
        help="last operations may be shells, as often as sweeps (labels: operator "
        "'shell', the opened face, rim strokes 1, a stroke down a wall 0); off by "
        "default, so that sets made without it stay the same",
    )
    p.add_argument(
        "--round-share",
        type=float,
        default=0.0,
        metavar="P",
        help="share (0 to 1) of the last bevels drawn as rounds, chamfers or profiles "
        "across an edge: circular rims, straight edges, their tangent chains and "
        "faces' outlines (datagen/rounds.py); default 0",
    )
    p.add_argument("--workers", type=int, default=2, help="processes (default 2)")
    p.add_argument(
        "--shard-size",
        type=int,
        default=SHARD_SIZE,
        help=f"samples per shard, a multiple of {PER_CONTEXT} (default {SHARD_SIZE})",
    )
    p.add_argument(
        "--ray",
        nargs="?",
        const="local",
        metavar="ADDRESS",
        help="run the shards as Ray tasks: on a local cluster of --workers CPUs, "
        "or on the running cluster at ADDRESS (host:port, 'auto'); the "
        "optional extra 'cluster'",
    )
    p.add_argument("--preview", type=Path, help="write a contact sheet of the first samples")
    p.add_argument(
        "--curved",
        action="store_true",
        help="every sample's operation stands on a cylinder's or cone's side (a "
        "held-out set for measuring operators on curved faces, or training "
        f"data for the head; one worker, shards of {SHARD_SIZE})",
    )


def out_problem(out: Path) -> str | None:
    """Why --out cannot be or become a data set's folder (it, or the nearest of its
    parents that exists, is a file or a link to nothing), or None."""
    for path in (out, *out.parents):
        if path.is_symlink() and not path.exists():
            return f"--out {out}: {path} is a link to {os.readlink(path)}, which does not exist"
        if path.exists():
            return None if path.is_dir() else f"--out {out}: {path} exists and is not a folder"
    return None


def run(args: argparse.Namespace) -> int:
    problem = out_problem(args.out)
    if problem:
        print(f"sketch2cad datagen: error: {problem}", file=sys.stderr)
        return 2
    if args.curved:
        if args.count <= 0:
            print("sketch2cad datagen: error: --curved needs a positive --count", file=sys.stderr)
            return 2
        if (
            args.ray is not None
            or args.hidden_lines != "draw"
            or args.regular_share
            or args.round_share
            or args.hand != "generator"
            or args.shells
        ):
            print(
                "sketch2cad datagen: error: --curved makes its set in one process with "
                "every line drawn and random parameters: leave out --ray, --hidden-lines, "
                "--regular-share, --round-share, --hand and --shells",
                file=sys.stderr,
            )
            return 2
        from datagen.curved import write_curved_set

        return write_curved_set(args.out, args.count, args.seed, args.noise_level)
    return generate_dataset(
        DatagenSettings(
            args.out,
            args.count,
            args.seed,
            args.noise_level,
            args.hidden_lines,
            args.workers,
            args.shard_size,
            args.preview,
            args.ray,
            args.regular_share,
            args.hand,
            args.shells,
            args.round_share,
        )
    )
