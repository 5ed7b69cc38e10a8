# SPDX-License-Identifier: LGPL-2.1-or-later
"""Replay PROTOCOL.json (schema in brep/protocol.py) and write the final solid.

`sketch2cad build PROTOCOL [--step OUT.step] [--png OUT.png] [--fcstd OUT.FCStd] [--quiet]`.
--fcstd runs FreeCAD's freecadcmd (or SKETCH2CAD_FREECADCMD) to save the model as a
PartDesign Body of native features (freecad_layer/partdesign).
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from pathlib import Path

from tqdm import tqdm

from ..brep.exchange import step_bytes
from ..brep.faces import OperationError
from ..brep.files import atomic_outputs, check_outputs
from ..brep.operators import build
from ..brep.protocol import Protocol, ProtocolError, load

# run by freecadcmd (not imported: it is FreeCAD's script)
SAVE_BODY = Path(__file__).resolve().parents[1] / "freecad_layer" / "partdesign" / "save_body.py"
PROGRESS_FROM = 20  # operations: a protocol this long shows a progress bar while it builds


def output_file(text: str) -> Path:
    """An output option's value: a file's path (argparse's `type`); an empty one is refused
    here, where the option can still be named."""
    if not text.strip():
        raise argparse.ArgumentTypeError("an empty path; give the file to write")
    return Path(text)


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("protocol", type=Path, help="protocol JSON file")
    p.add_argument("--step", type=output_file, help="write the solid as STEP AP214 (mm)")
    p.add_argument("--png", type=output_file, help="write a shaded picture (PNG)")
    p.add_argument(
        "--fcstd",
        type=output_file,
        help="write a FreeCAD document holding the model as a PartDesign Body (needs FreeCAD)",
    )
    p.add_argument("--quiet", action="store_true", help="do not print the protocol listing")


def write_outputs(
    solid,
    protocol: Protocol | None,
    step: Path | None,
    png: Path | None,
    protocol_path: Path | None = None,
    fcstd: Path | None = None,
) -> None:
    """Write the asked-for outputs of a command all or none: each to a temporary beside it,
    moved into place only when every one was written (brep/files.py).

    Raises:
        OSError: an output could not be written; no file was replaced.
    """
    outputs = []
    if protocol_path:
        outputs.append((protocol_path, lambda: protocol.file_text().encode()))
    if step:
        outputs.append((step, lambda: step_bytes(solid)))
    if png:
        # VTK only when a picture is asked for
        from ..render.picture import png_bytes, shaded_picture

        outputs.append((png, lambda: png_bytes(shaded_picture(solid))))
    if fcstd:
        if protocol is None:
            raise ValueError("--fcstd needs the protocol the solid was built from")
        model = protocol
        outputs.append((fcstd, lambda: fcstd_bytes(model)))
    for path, _ in outputs:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
        except FileExistsError as e:  # OSError's text names the file alone, not why
            raise OSError(
                f"{path}: cannot make its folder: {e.filename} is a file, not a folder"
            ) from None
    with atomic_outputs([path for path, _ in outputs]) as tmps:
        for tmp, (_, data) in zip(tmps, outputs, strict=False):
            tmp.write_bytes(data())


def replay_progress(steps: int, what: str) -> tqdm:
    """A progress bar on stderr over `steps` steps of a replay: shown where stderr is a
    terminal, or the replay has PROGRESS_FROM steps or more (a long one says how far it is
    in a log too). Lines printed meanwhile go through `tqdm.write`, which keeps the bar
    below them."""
    shown = sys.stderr.isatty() or steps >= PROGRESS_FROM
    return tqdm(total=steps, desc=what, unit="step", leave=False, disable=not shown)


def freecadcmd() -> str:
    """FreeCAD's command-line executable: SKETCH2CAD_FREECADCMD, else freecadcmd (or
    FreeCADCmd) on the PATH.

    Raises:
        ValueError: FreeCAD is not installed (saying how to point at it).
    """
    exe = os.environ.get("SKETCH2CAD_FREECADCMD") or next(
        (shutil.which(n) for n in ("freecadcmd", "FreeCADCmd") if shutil.which(n)), None
    )
    if not exe:
        raise ValueError(
            "--fcstd needs FreeCAD: no freecadcmd (or FreeCADCmd) on the PATH; install FreeCAD "
            "0.20 or newer, or set SKETCH2CAD_FREECADCMD to its freecadcmd"
        )
    return exe


def fcstd_bytes(protocol: Protocol) -> bytes:
    """The protocol's model as a FreeCAD document of PartDesign Bodies, saved through
    freecadcmd (freecad_layer/partdesign/save_body.py) into a temporary folder.

    Raises:
        OSError: FreeCAD failed (its message) or wrote nothing.
    """
    import tempfile

    with tempfile.TemporaryDirectory() as tmp:
        source = Path(tmp) / "protocol.json"
        source.write_text(protocol.to_json())
        path = Path(tmp) / "model.FCStd"
        env = dict(os.environ, SKETCH2CAD_PROTOCOL=str(source), SKETCH2CAD_FCSTD=str(path))
        env.pop("PYTHONPATH", None)  # FreeCAD's own Python set-up
        done = subprocess.run(
            [freecadcmd(), str(SAVE_BODY)], env=env, capture_output=True, text=True, cwd=tmp
        )
        lines = [s for s in done.stdout.splitlines() if s.startswith(("  -> ", "  step "))]
        print("\n".join(lines))
        if done.returncode != 0 or not path.exists():
            raise OSError(f"FreeCAD could not save the document: {done.stderr.strip()[-2000:]}")
        return path.read_bytes()


def build_files(
    protocol_path: Path,
    step: Path | None,
    png: Path | None,
    quiet: bool = False,
    fcstd: Path | None = None,
):
    """Replay one protocol file and write its outputs (all or none); returns the solid.

    Raises:
        ValueError: an output is the protocol file or another output; --fcstd without
            FreeCAD.
    """
    check_outputs({"PROTOCOL": protocol_path}, {"--step": step, "--png": png, "--fcstd": fcstd})
    if fcstd:
        freecadcmd()  # before any work
    protocol = load(protocol_path)
    if not quiet:
        print(f"{protocol_path}:\n{protocol.listing()}")
    with replay_progress(len(protocol.operations), f"build {protocol_path.name}") as bar:
        solid = build(protocol, on_step=lambda i: bar.update(1))
    write_outputs(solid, protocol, step, png, fcstd=fcstd)
    if not quiet:
        bb = solid.BoundingBox()
        print(
            f"  -> volume {solid.Volume():.2f} mm^3, size {bb.xlen:.1f} x {bb.ylen:.1f} x "
            f"{bb.zlen:.1f} mm" + (f", {step}" if step else "") + (f", {png}" if png else "")
        )
    return solid


def run(args: argparse.Namespace) -> int:
    try:
        build_files(args.protocol, args.step, args.png, args.quiet, args.fcstd)
    except (ProtocolError, OperationError, OSError, ValueError) as e:
        print(f"sketch2cad build: error: {e}", file=sys.stderr)
        return 2
    return 0
