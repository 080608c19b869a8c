"""README.md and docs/*.md as a tested guide (Python): every fenced block marked
```` ```python test ```` runs as written with the installed package, in order per file, in
one fresh folder outside the checkout, and exits 0."""

import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[3]


def marked_blocks(markdown, language="python"):
    """The blocks whose info string is ``<language> test``, with their first line numbers."""
    blocks, inside, taken, lines, start = [], False, False, [], 0
    for i, line in enumerate(markdown.splitlines()):
        stripped = line.strip()
        if not inside and stripped.startswith("```"):
            info = stripped[3:].split()
            inside, taken, lines, start = True, info[:1] == [language] and "test" in info, [], i + 2
        elif inside and stripped == "```":
            if taken:
                blocks.append((start, "\n".join(lines) + "\n"))
            inside = False
        elif inside:
            lines.append(line)
    return blocks


def guides():
    return [REPO / "README.md", *sorted((REPO / "docs").glob("*.md"))]


def test_the_extraction_takes_only_marked_blocks():
    md = "```python test\nprint(1)\n```\n```python\nprint(2)\n```\n```sh test\nls\n```\n"
    assert marked_blocks(md) == [(2, "print(1)\n")]


def test_every_python_block_runs_as_written(tmp_path):
    count = 0
    for guide in guides():
        if not guide.is_file():
            continue
        work = tmp_path / guide.stem
        work.mkdir()
        for line, block in marked_blocks(guide.read_text(encoding="utf-8")):
            script = work / f"block_{line}.py"
            script.write_text(block)
            done = subprocess.run(
                [sys.executable, script.name], cwd=work, capture_output=True, text=True
            )
            assert done.returncode == 0, f"{guide}:{line}\n{block}\n{done.stdout}\n{done.stderr}"
            count += 1
    assert count >= 3
