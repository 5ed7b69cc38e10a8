# SPDX-License-Identifier: LGPL-2.1-or-later
"""FreeCAD driven from outside, as a designer drives it: real X mouse and key events
(xdotool) on a 1366 x 768 virtual screen (Xvfb) with a window manager (openbox), strokes
drawn by a hand that wobbles and overshoots, and screenshots (xwd). FreeCAD runs
scripts/x_session.py, which sets up a model, opens the Sketch panel and only reports
what is on the screen (state.json); every click, drag and key comes from here.

Each runs in FreeCAD's default layout (FreeCAD 1.1's Tasks panel floats over the 3D
view's right side); a test that takes `overlay` runs, on FreeCAD 1.1, again with every
panel floating over the view (Toggle overlay for all); FreeCAD 0.20 and 1.0 have no
overlay mode."""

import contextlib
import itertools
import json
import os
import re
import shutil
import signal
import subprocess
import time

import numpy as np
import pytest
from freecad_process import SCRIPTS, freecad_env

from Sketch2CADWorkbench.render.camera import OrthoCamera
from Sketch2CADWorkbench.sketch.curves import silhouette_side

pytestmark = [pytest.mark.freecad, pytest.mark.gui]
SCREEN = (1366, 768)
TOOLS = ("Xvfb", "openbox", "xdotool", "xwd", "freecad")


class Desktop:
    """Xvfb, openbox and FreeCAD running scripts/x_session.py; X events from xdotool."""

    def __init__(self, tmp_path, overlay: bool):
        for tool in TOOLS:
            assert shutil.which(tool), f"{tool} is not installed (scripts/setup.sh installs it)"
        self.tmp = tmp_path
        self.procs = []
        read, write = os.pipe()
        xvfb = subprocess.Popen(
            [
                "Xvfb",
                "-displayfd",
                str(write),
                "-dpi",
                "96",
                "-screen",
                "0",
                f"{SCREEN[0]}x{SCREEN[1]}x24",
            ],
            pass_fds=(write,),
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            start_new_session=True,
        )
        self.procs.append(xvfb)
        os.close(write)
        with os.fdopen(read) as f:
            self.display = ":" + f.readline().strip()
        self.env = dict(freecad_env(tmp_path), DISPLAY=self.display)
        self.env["SKETCH2CAD_OVERLAY"] = "1" if overlay else "0"
        self.spawn(["openbox"])
        self.log = open(tmp_path / "freecad.log", "w")  # noqa: SIM115 (open while FreeCAD runs)
        self.spawn(["freecad", str(SCRIPTS / "x_session.py")], out=self.log)

    def spawn(self, cmd, out=subprocess.DEVNULL) -> None:
        self.procs.append(
            subprocess.Popen(
                cmd, env=self.env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True
            )
        )

    def close(self) -> None:
        for p in reversed(self.procs):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(p.pid, signal.SIGKILL)
            p.wait()
        self.log.close()

    def output(self) -> str:
        self.log.flush()
        return (self.tmp / "freecad.log").read_text(errors="replace")[-4000:]

    # ------------------------------------------------------------ what FreeCAD shows

    def state(self) -> dict:
        try:
            return json.loads((self.tmp / "state.json").read_text())
        except (FileNotFoundError, json.JSONDecodeError):
            return {}

    def wait(self, what, timeout: float = 60.0) -> dict:
        """The first state for which `what(state)` holds, written after this call (a busy
        FreeCAD writes none: it has not seen the last events yet), when two reports in a
        row agree (the view's animations have ended)."""
        start, end, last = time.time(), time.monotonic() + timeout, None
        while time.monotonic() < end:
            s = self.state()
            fresh = s.get("time", 0) > start + 0.2
            # a modal dialog takes every mouse event: no step of the test can follow
            assert not (fresh and s.get("modal")), f"a modal dialog is open: {s['modal']}"
            if fresh and "error" not in s and what(s) and _same(s, last):
                return s
            last = s if fresh else None
            time.sleep(0.25)
        raise AssertionError(f"timed out; last state {json.dumps(last)[:3000]}\n{self.output()}")

    def screenshot(self, name: str) -> np.ndarray:
        """The whole X screen (xwd), as an RGB array; also written as NAME.png."""
        raw = subprocess.run(
            ["xwd", "-root", "-silent"], env=self.env, capture_output=True, check=True
        ).stdout
        image = _xwd_rgb(raw)
        try:
            import cv2

            cv2.imwrite(str(self.tmp / f"{name}.png"), image[:, :, ::-1])
        except ImportError:
            pass
        return image

    # ------------------------------------------------------------ what the user does

    def xdo(self, *args) -> None:
        subprocess.run(["xdotool", *map(str, args)], env=self.env, check=True)

    def click(self, x, y) -> None:
        """Move there, rest as a hand does (FreeCAD 1.1's overlay panels wake on hover),
        click."""
        self.xdo("mousemove", int(x), int(y), "sleep", 0.6, "click", 1)

    def click_button(self, s: dict, text: str) -> None:
        """Click the button labelled `text`, which must be seen whole: on the screen and,
        in the panel, within the part of the Tasks area shown (not scrolled away)."""
        (x, y, w, h) = r = button(s, text)
        assert inside(r, (0, 0, *SCREEN)), (text, r)
        p = s["panel"]
        if p is not None and p["area"] is not None and inside(r, p["form"]):
            assert inside(r, p["area"]), f"{text} {r} lies outside the Tasks area {p['area']}"
        self.click(x + w / 2, y + h / 2)

    def drag(self, points) -> None:
        """Press at the first screen point, move through the others, release: one stroke."""
        args = ["mousemove", int(points[0][0]), int(points[0][1]), "sleep", 0.05, "mousedown", 1]
        for x, y in points[1:]:
            args += ["mousemove", round(x), round(y), "sleep", 0.01]
        args += ["sleep", 0.05, "mouseup", 1]
        self.xdo(*args)

    def key(self, name: str) -> None:
        self.xdo("key", name)

    def sketch(self, strokes, read=lambda s: s["panel"]["kind"] is not None) -> dict:
        """Draw the strokes in the open Sketch panel and press Return: the state once the
        panel shows them all and then its reading (`read(state)`)."""
        for stroke in strokes:
            self.drag(stroke)
        self.wait(lambda s: panel_open(s) and s["panel"]["strokes"] == len(strokes))
        self.key("Return")
        return self.wait(lambda s: panel_open(s) and read(s), timeout=120)

    def open_panel(self, s: dict) -> dict:
        """Focus the 3D view with a click and open the Sketch panel by its shortcut (S, S)."""
        self.click(*np.add(s["viewport"][:2], np.divide(s["viewport"][2:], 2)))
        self.key("s")
        self.key("s")
        return self.wait(panel_open)


def _same(a: dict, b: dict | None) -> bool:
    """Two reports show the same (when they were written aside)."""
    return b is not None and {**a, "time": 0} == {**b, "time": 0}


def _xwd_rgb(raw: bytes) -> np.ndarray:
    """An X window dump (xwd) of a TrueColor screen (24 or 32 bits a pixel) as an
    (H, W, 3) RGB array."""
    header = np.frombuffer(raw[:100], ">u4").astype(int)
    size, width, height, byte_order = header[0], header[4], header[5], header[7]
    bits, line, masks, colours = header[11], header[12], header[14:17], header[19]
    assert bits in (24, 32), f"xwd: {bits} bits a pixel"
    start = size + 12 * colours
    rows = np.frombuffer(raw[start : start + line * height], np.uint8).reshape(height, line)
    n = bits // 8
    pixels = rows[:, : width * n].reshape(height, width, n).astype(np.uint32)
    order = range(n) if byte_order == 0 else range(n - 1, -1, -1)  # LSB or MSB first
    value = sum(pixels[:, :, i] << (8 * k) for k, i in enumerate(order))
    shifts = [(int(m) & -int(m)).bit_length() - 1 for m in masks]
    return np.stack(
        [(value & m) >> s for m, s in zip(masks, shifts, strict=False)], axis=-1
    ).astype(np.uint8)


def button(s: dict, text: str) -> list:
    """The screen rectangle of the visible button labelled `text`."""
    found = [r for t, r, _ in s["buttons"] if t == text]
    assert found, f"no visible button {text!r} among {[t for t, _, _ in s['buttons']]}"
    return found[-1]


def checked(s: dict, text: str) -> bool:
    return [c for t, _, c in s["buttons"] if t == text][-1]


def to_screen(s: dict, world) -> np.ndarray:
    """World points (mm) -> screen points, through the view's camera and viewport."""
    c = s["camera"]
    cam = OrthoCamera(
        tuple(c["center"]),
        tuple(c["direction"]),
        tuple(c["up"]),
        c["scale"],
        c["width"],
        c["height"],
    )
    x, y = s["viewport"][:2]  # the camera's pixels are the screen's
    return cam.project(np.asarray(world, float))[0] + (x, y)


def wobbly(a, b, rng, wobble: float = 1.5, overshoot: float = 0.06, step: float = 4.0):
    """A hand's stroke from screen point a to b: it overshoots both ends, its line sways
    side to side and jitters (pixels)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    n = max(8, int(np.linalg.norm(b - a) / step))
    t = np.linspace(-overshoot * rng.uniform(0.3, 1), 1 + overshoot * rng.uniform(0.3, 1), n)
    d = (b - a) / max(np.linalg.norm(b - a), 1e-9)
    side = np.array([-d[1], d[0]])
    sway = wobble * np.sin(2 * np.pi * (rng.uniform(0.6, 1.4) * t + rng.uniform(0, 1)))
    jitter = rng.normal(0, 0.4, n)
    return a + np.outer(t, b - a) + np.outer(sway + jitter, side)


def in_one_go(points, rng) -> np.ndarray:
    """One stroke through screen points in order, the pen not lifted at the corners (as
    a person draws a rectangle)."""
    legs = [wobbly(a, b, rng, overshoot=0.0) for a, b in itertools.pairwise(points)]
    return np.vstack([legs[0]] + [leg[1:] for leg in legs[1:]])


BOX = (40.0, 30.0, 20.0)  # the New model command's box (mm), centred on the origin


def pad_strokes(s: dict, height: float, rng) -> list:
    """The strokes of the box's top face pulled up by `height`, as a hand draws them."""
    lx, ly, lz = BOX
    top = np.array([[x, y, lz / 2] for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))], float)
    top[:, 0] *= lx / 2
    top[:, 1] *= ly / 2
    up = top + [0, 0, height]
    lines = [(up[i], up[(i + 1) % 4]) for i in range(4)] + list(zip(top, up, strict=False))
    return [wobbly(*to_screen(s, [a, b]), rng) for a, b in lines]


def prism_strokes(s: dict, base, offset, rng, split_edge: int | None = None) -> list:
    """A prism on a face of the box: its base polygon `base` (world, mm) and the same
    moved by `offset`, each outline drawn in one stroke unless `split_edge` is given (then
    one stroke per edge, that edge of the base in two strokes that overlap a little), and
    one depth line from each corner."""
    base = np.asarray(base, float)
    far = base + offset
    k = len(base)
    if split_edge is None:
        outlines = [in_one_go(to_screen(s, np.vstack([p, p[:1]])), rng) for p in (base, far)]
    else:
        outlines = [
            wobbly(*to_screen(s, [p[i], p[(i + 1) % k]]), rng)
            for p in (base, far)
            for i in range(k)
            if p is far or i != split_edge
        ]
        a, b = to_screen(s, [base[split_edge], base[(split_edge + 1) % k]])
        outlines += [wobbly(a, a + 0.55 * (b - a), rng), wobbly(a + 0.45 * (b - a), b, rng)]
    depth = [wobbly(*to_screen(s, [p, p + offset]), rng) for p in base]
    return outlines + depth


def cylinder_strokes(s: dict, centre, axis, radius: float, length: float, gap: float, rng):
    """A cylinder standing on a face of the box: the circle on the face left open by a
    `gap` (a share of its turn), the far circle whole, the two silhouette lines, each in
    one stroke."""
    axis = np.asarray(axis, float)
    side = silhouette_side(axis, np.asarray(s["camera"]["direction"], float))
    other = np.cross(axis, side)
    start = rng.uniform(0, 2 * np.pi)

    def circle(at, share):
        t = start + np.linspace(0, 2 * np.pi * share, 90)
        ring = at + radius * (np.cos(t)[:, None] * side + np.sin(t)[:, None] * other)
        return to_screen(s, ring) + rng.normal(0, 0.4, (len(t), 2))

    far = np.add(centre, length * axis)
    lines = [
        wobbly(*to_screen(s, [np.add(c, k * radius * side) for c in (centre, far)]), rng)
        for k in (1, -1)
    ]
    return [circle(centre, 1 - gap), circle(far, 1.0)] + lines


def panel_open(s: dict) -> bool:
    return s.get("panel") is not None


def inside(r, outer) -> bool:
    """Rectangle r ([x, y, w, h]) lies within `outer`."""
    x, y, w, h = r
    ox, oy, ow, oh = outer
    return x >= ox and y >= oy and x + w <= ox + ow and y + h <= oy + oh


def inside_screen(r, screen) -> bool:
    return inside(r, (0, 0, *screen))


def freecad_has_overlay_mode() -> bool:
    out = subprocess.run(
        ["freecadcmd", "-c", "import FreeCAD; print('VERSION', *FreeCAD.Version()[:2])"],
        capture_output=True,
        text=True,
        timeout=120,
    ).stdout
    major, minor = (int(v) for v in out.split("VERSION")[-1].split()[:2])
    return (major, minor) >= (1, 1)


def pytest_generate_tests(metafunc):
    """The layouts this FreeCAD has: its default one, and from FreeCAD 1.1 on the overlay
    mode for all panels."""
    if "overlay" in metafunc.fixturenames:
        layouts = [False, True] if freecad_has_overlay_mode() else [False]
        ids = ["default_layout", "overlay_for_all"][: len(layouts)]
        metafunc.parametrize("overlay", layouts, ids=ids)


@pytest.fixture
def desktop(request, tmp_path, run_freecad):  # run_freecad: the user config is primed
    """The desktop in the test's layout (`overlay`), or FreeCAD's default one."""
    overlay = "overlay" in request.fixturenames and request.getfixturevalue("overlay")
    d = Desktop(tmp_path, overlay=overlay)
    try:
        yield d
    finally:
        d.close()


def test_a_designer_with_a_mouse(desktop, overlay):  # in each layout
    """The panel fits the screen; a drag from the overlay panel's edge draws nothing; the
    check box shows its state; a wobbly pad is read as a Pad and OK adds it; a scribble
    is not added by OK but by Add anyway."""
    d = desktop
    rng = np.random.default_rng(7)
    s = d.wait(lambda s: panel_open(s) and s["features"], timeout=120)
    assert np.allclose(s["screen"], SCREEN, atol=2), s["screen"]
    p = s["panel"]
    shot = d.screenshot("panel")
    # the whole panel is on the screen, not cut off at its edge, without a sideways scroll
    assert inside_screen(p["form"], SCREEN) or (
        p["area"] is not None and inside_screen(p["area"], SCREEN)
    ), (p["form"], p["area"])
    assert not p["hscroll"], p
    for text in ("Interpret", "Clear strokes"):
        assert inside_screen(button(s, text), SCREEN), (text, button(s, text))
    # what the screenshot shows where the panel is: not the screen's black
    x, y, w, h = p["area"] or p["form"]
    assert shot[y : y + h, x : x + w].mean() > 60, "the panel is not drawn on the screen"

    if s["overlay_mode"]:
        assert p["overlay"] is not None, "the Sketch panel is not in an overlay panel"
    if p["overlay"] is not None:
        # a drag that starts on the overlay panel's edge that faces the view resizes the
        # panel; it draws no stroke
        ox, oy, ow, oh = p["overlay"]
        vx, _, vw, _ = s["viewport"]
        toward = -1 if ox + ow / 2 > vx + vw / 2 else 1  # a panel on the right: its left edge
        edge = np.array([ox + 2 if toward < 0 else ox + ow - 3, oy + oh // 2])
        d.xdo("mousemove", *edge, "sleep", 0.6)
        d.drag([edge + (toward * k, k // 10) for k in range(0, 80, 8)])
        s = d.wait(panel_open)
        d.screenshot("overlay_edge_dragged")
        assert s["panel"]["strokes"] == 0, "a drag on the overlay panel's edge drew a stroke"

    # the check box shows its state: its pixels change when it is clicked
    box = s["panel"]["regularize"]
    bx, by, bw, bh = box
    label = "Regularize (snap and rectify)"
    d.xdo("mousemove", bx + bh // 2, by + bh // 2, "sleep", 0.6)  # the panel wakes on hover
    before = d.screenshot("check_on")[by : by + bh, bx : bx + min(bw, bh + 4)].astype(int)
    d.click(bx + bh / 2, by + bh / 2)
    s = d.wait(lambda s: panel_open(s) and not checked(s, label), timeout=10)
    after = d.screenshot("check_off")[by : by + bh, bx : bx + min(bw, bh + 4)].astype(int)
    d.click(bx + bh / 2, by + bh / 2)  # back on
    s = d.wait(lambda s: panel_open(s) and checked(s, label), timeout=10)
    assert np.abs(before - after).sum(axis=-1).max() > 100, "the check box shows no tick"

    # a pad drawn with a wobbling hand is read as a Pad; OK adds it
    s = d.sketch(pad_strokes(d.wait(panel_open), 10.0, rng))
    d.screenshot("pad_read")
    text = s["panel"]["text"]
    assert "Read as Pad" in text and re.search(r"moved out by 10(\.0+)? mm", text), text
    assert inside_screen(button(s, "OK"), SCREEN), button(s, "OK")
    d.click_button(s, "OK")
    s = d.wait(lambda s: not panel_open(s) and len(s["features"]) == 2)
    assert s["features"][-1][0] == "Pad" and s["features"][-1][2], s["features"]
    assert abs(s["features"][-1][1] - 40 * 30 * 30) < 1e-6 * 40 * 30 * 30, s["features"]

    # a scribble: OK does not add it, Add anyway does
    s = d.open_panel(s)
    centre = to_screen(s, [[0.0, 0.0, 20.0]])[0]
    walks = [centre + np.cumsum(rng.normal(0, 9, (25, 2)), axis=0) for _ in range(4)]
    s = d.sketch(walks, read=lambda s: s["panel"]["text"] not in ("", "Networks ready."))
    d.screenshot("scribble_read")
    p = s["panel"]
    if p["kind"] is not None:  # read as something: flagged, not added by OK
        assert p["doubtful"] and p["anyway"], p["text"]
        d.click_button(s, "OK")
        time.sleep(1.0)
        s = d.wait(panel_open)
        assert len(s["features"]) == 2 and "Not added" in s["panel"]["text"], s["panel"]["text"]
        d.click_button(s, "Add anyway")
        s = d.wait(lambda s: not panel_open(s) and len(s["features"]) == 3)
    else:  # not read at all: the panel says why and adds nothing
        assert "Not interpreted" in p["text"], p["text"]


def hand_curve(points, rng, jitter: float = 0.5) -> np.ndarray:
    """A hand's stroke along screen points (K, 2): it jitters (pixels)."""
    return np.asarray(points, float) + rng.normal(0, jitter, (len(points), 2))


def drilled_hole_strokes(s: dict, rng, r: float = 6.0, depth: float = 15.0) -> list:
    """A cylindrical hole r 6 mm, 15 deep into the box's front face (-Y) as a designer
    draws it: the rim circle on the face, the two depth lines into the body, and the
    part of the bottom circle away from the viewer (the near part lies behind the rim)."""
    centre, axis = np.array([0.0, -15.0, 0.0]), np.array([0.0, 1.0, 0.0])  # into the body
    view = np.array(s["camera"]["direction"], float)
    side = np.cross(axis, view)
    side /= np.linalg.norm(side)
    other = np.cross(axis, side)
    t = np.linspace(0, 2 * np.pi, 73)
    ring = np.cos(t)[:, None] * side + np.sin(t)[:, None] * other
    rim, bottom = centre + r * ring, centre + depth * axis + r * ring
    far = bottom[(bottom - bottom.mean(axis=0)) @ view > 0]
    far = far[
        np.argsort(
            np.arctan2((far - bottom.mean(axis=0)) @ other, (far - bottom.mean(axis=0)) @ side)
        )
    ]
    strokes = [hand_curve(to_screen(s, rim), rng), hand_curve(to_screen(s, far), rng)]
    for k in (1, -1):
        a = centre + k * r * side
        strokes.append(wobbly(*to_screen(s, [a, a + depth * axis]), rng))
    return strokes


def test_a_hole_drawn_into_the_front_face_is_read_as_a_hole(desktop):
    """A cylindrical hole drawn into the box's front face (-Y) with a wobbling hand, the
    Boolean on auto, is read as a hole and OK cuts it; at worst the hole is the other
    reading, one click away, and that click gives the hole. Either way the other
    Boolean has its button."""
    d = desktop
    rng = np.random.default_rng(11)
    s = d.wait(lambda s: panel_open(s) and s["features"], timeout=120)
    box = s["features"][0][1]
    s = d.sketch(drilled_hole_strokes(s, rng))
    d.screenshot("hole_read")
    offered = [t for t, _, _ in s["buttons"] if t in ("Hole", "Groove")]
    if offered and not checked(s, offered[0]):  # read as a boss: the hole, one click away
        d.click_button(s, offered[0])
        s = d.wait(lambda s: panel_open(s) and checked(s, offered[0]))
        d.screenshot("hole_chosen")
    else:
        assert "(subtract)" in s["panel"]["text"], s["panel"]["text"]
        # read as the hole, the boss on its rim is one click away
        assert {"Boss", "Revolution"} & {t for t, _, _ in s["buttons"]}, s["buttons"]
    d.click_button(s, "OK")
    s = d.wait(lambda s: not panel_open(s) and len(s["features"]) == 2)
    label, volume, valid = s["features"][-1]
    cut = box - volume
    assert valid and label.startswith(("Hole", "Groove")), s["features"]
    assert 0.6 * np.pi * 36 * 15 < cut < 1.4 * np.pi * 36 * 15, (cut, s["features"])


def test_strokes_drawn_as_people_draw_them(desktop):
    """A prism whose outlines are each drawn in one stroke, a prism with a long edge of its
    base drawn in two strokes, and a cylinder whose circle on the face is left open: each
    is read as the primitive drawn, and OK adds it with about the size drawn."""
    d = desktop
    rng = np.random.default_rng(11)
    lx, ly, lz = BOX
    s = d.wait(lambda s: panel_open(s) and s["features"], timeout=120)
    volume = s["features"][-1][1]
    steps = [  # (kind, strokes from the view's state, volume added)
        (  # a 20 x 15 mm boss 10 mm high on the top face, each rectangle in one stroke
            "Boss",
            lambda s: prism_strokes(
                s,
                [(-15, -10, lz / 2), (5, -10, lz / 2), (5, 5, lz / 2), (-15, 5, lz / 2)],
                (0, 0, 10),
                rng,
            ),
            20 * 15 * 10,
        ),
        (  # a 28 x 10 mm hole 8 mm deep into the front face, its bottom edge in two strokes
            "Hole",
            lambda s: prism_strokes(
                s,
                [(-14, -ly / 2, -5), (14, -ly / 2, -5), (14, -ly / 2, 5), (-14, -ly / 2, 5)],
                (0, 8, 0),
                rng,
                split_edge=0,
            ),
            -28 * 10 * 8,
        ),
        (  # a cylinder of radius 8 mm, 10 mm long, on the right face, its base circle open
            "Revolution",
            lambda s: cylinder_strokes(s, (lx / 2, 3, 0), (1, 0, 0), 8.0, 10.0, 0.15, rng),
            np.pi * 8**2 * 10,
        ),
    ]
    for n, (kind, strokes, added) in enumerate(steps):
        if n:
            s = d.open_panel(s)
        s = d.sketch(strokes(s))
        d.screenshot(f"{kind}_read")
        assert f"Read as {kind}" in s["panel"]["text"], s["panel"]["text"]
        d.click_button(s, "OK")
        s = d.wait(lambda s, n=n: not panel_open(s) and len(s["features"]) == n + 2)
        label, now, valid = s["features"][-1]
        assert label == kind and valid, s["features"]
        assert abs(now - volume - added) < 0.2 * abs(added), (kind, now - volume, added)
        volume = now


def test_a_shell_drawn_as_its_rim_in_one_stroke_is_read_as_a_thickness(desktop):
    """The inner rim of a box opened at its top, 3 mm in from the top face's outline,
    drawn in one stroke with a wobbling hand, is read as a Thickness; OK hollows the box
    with walls about that thick."""
    d = desktop
    rng = np.random.default_rng(5)
    lx, ly, lz = BOX
    t = 3.0
    s = d.wait(lambda s: panel_open(s) and s["features"], timeout=120)
    box = s["features"][-1][1]
    rim = [
        (x * (lx / 2 - t), y * (ly / 2 - t), lz / 2)
        for x, y in ((-1, -1), (1, -1), (1, 1), (-1, 1))
    ]
    s = d.sketch([in_one_go(to_screen(s, rim + rim[:1]), rng)])
    d.screenshot("thickness_read")
    assert "Read as Thickness" in s["panel"]["text"], s["panel"]["text"]
    d.click_button(s, "OK")
    s = d.wait(lambda s: not panel_open(s) and len(s["features"]) == 2)
    label, volume, valid = s["features"][-1]
    assert label.startswith("Thickness") and valid, s["features"]
    walls = box - (lx - 2 * t) * (ly - 2 * t) * (lz - t)  # the floor t thick too
    assert abs(volume - walls) < 0.2 * walls, (volume, walls)
