# SPDX-License-Identifier: LGPL-2.1-or-later
"""The repository describes the project as it is now, not how it got there.

No tracked text file names a working session by its number, a tracker's issue number, a
scratch folder or the team's workspace, a member of the team, or the dated engineering
diary the documentation replaced. Say the requirement
itself instead ("median interpret time at most 100 ms"); history belongs in git.

The examples the patterns are checked against are put together from pieces, so that this
file does not name what it forbids.
"""

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# What a citation of the project's history looks like. Each pattern is narrow enough to
# leave ordinary words alone: a timer's stop(), a hex colour, a "scratch document".
HISTORY = {
    "a working session's number": re.compile(r"\b[Ss]tops? ?-?\d+"),
    # a number after '#' that follows the start of a line, a space or an opening bracket:
    # not a hex colour (after a quote or a colon, or ending in ';') nor an HTML entity
    "a tracker number": re.compile(r"(?:^|(?<=[\s(\[]))#\d+\b(?!;)", re.M),
    "a scratch folder": re.compile(r"(?<![\w.])(?:/wo" r"rk/|scra" r"tch/)"),
    "a member of the team": re.compile(r"\b[Dd]eveloper [A-E]\b|\b[Tt]he lead(?:'s)?\b"),
    "the removed engineering diary": re.compile(r"\bNOTES\.md\b"),
}


def history_citations(text: str) -> list[tuple[int, str, str]]:
    """(line number, kind, the matched text) of every history citation in `text`."""
    found = []
    for kind, pattern in HISTORY.items():
        for m in pattern.finditer(text):
            found.append((text.count("\n", 0, m.start()) + 1, kind, m.group(0)))
    return sorted(found)


def tracked_texts(root: Path) -> dict[str, str]:
    """Every file git tracks under `root` that is text (UTF-8, no NUL byte), by path."""
    listing = subprocess.run(
        ["git", "ls-files", "-z"], cwd=root, capture_output=True, check=True
    ).stdout.decode()
    texts = {}
    for name in filter(None, listing.split("\0")):
        path = root / name
        if not path.is_file():  # deleted in the work tree, not yet committed
            continue
        data = path.read_bytes()
        if b"\0" in data:
            continue
        try:
            texts[name] = data.decode("utf-8")
        except UnicodeDecodeError:
            continue
    return texts


@pytest.mark.parametrize(
    "text",
    [
        "Tried at st" + "op 12",
        "the head of st" + "ops 26-32",
        "S" + "top 24 found",
        "a st" + "op-38 note",
        "(#" + "16, beyond the paper)",
        "see #" + "17 item 1",
        "#" + "12: impossible values",
        "see `/wo" + "rk/scra" + "tch/s38/own.sh`",
        "datagen --out scra" + "tch/val-l3",
        "(develo" + "per E)",
        "the le" + "ad's figures",
        "measured in docs/NO" + "TES.md",
    ],
)
def test_a_citation_of_the_projects_history_is_found(text):
    assert history_citations(text), text


@pytest.mark.parametrize(
    "text",
    [
        "self.timer.stop()",
        "# stop at the apex, where r(h) = 0",
        '<path style="fill:#000000;stroke:#2e3436"/>',
        'fill="#729fcf"',
        "&#160;",
        "color: #333;",
        "# 1. the base face",
        "x = y  # 2 px",
        "the training data from scratch",
        'scratch = FreeCAD.newDocument("Export")',
        "docs/workbench.png",
        "a designer draws",
        "leads to a hole",
        "the leading edge",
    ],
)
def test_ordinary_text_is_not_taken_for_history(text):
    assert not history_citations(text), history_citations(text)


def test_no_tracked_file_cites_the_projects_history():
    texts = tracked_texts(ROOT)
    assert "README.md" in texts and "pyproject.toml" in texts, "git ls-files found no files"
    cited = [
        f"{name}:{line}: {kind}: {match!r}"
        for name, text in sorted(texts.items())
        for line, kind, match in history_citations(text)
    ]
    assert not cited, "history cited (say the requirement instead):\n" + "\n".join(cited)


# "docs/measurements.md, module.NAME" or "docs/measurements.md, "A section's title"
POINTER = re.compile(r'measurements\.md,\s+(?:#\s+)?(?:([a-z_.]+\.[A-Z][A-Z_]+)|"([^"\n]+))')


def measurement_rows(text: str) -> set[str]:
    """The names a row of docs/measurements.md stands for: "m.A, B" gives m.A and m.B."""
    names = set()
    for line in text.splitlines():
        if not line.startswith("| ") or line.startswith("| row"):
            continue
        first, *others = (n.strip() for n in line.split("|")[1].split(","))
        module = first.rpartition(".")[0]
        names.add(first)
        names.update(f"{module}.{n}" for n in others)
    return names


def test_every_pointer_to_a_measurement_names_a_row_or_section():
    text = (ROOT / "docs" / "measurements.md").read_text(encoding="utf-8")
    rows = measurement_rows(text)
    flat = " ".join(text.split())
    missing = [
        f"{name}: {match.group(0)!r}"
        for name, source in sorted(tracked_texts(ROOT).items())
        if name.endswith(".py") and name != "tests/test_repository_text.py"
        for match in POINTER.finditer(source)
        if (match.group(1) and match.group(1) not in rows)
        or (match.group(2) and " ".join(match.group(2).split()) not in flat)
    ]
    assert rows and not missing, "pointers to no row of docs/measurements.md:\n" + "\n".join(
        missing
    )
