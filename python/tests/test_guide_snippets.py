"""Every Python snippet of the guide (README.md and docs/**/*.md) runs as
written, saved as a script: each ```python block is written to a file in
an empty temporary folder and run by this interpreter in a subprocess
(a snippet that starts worker processes, as the dask example does, needs
its ``if __name__ == "__main__":`` guard there, which ``python -c`` or a
notebook would hide).

A snippet that cannot run on a test machine says so in an HTML comment on
the line just before its fence (invisible in the rendered guide), with the
reason::

    <!-- snippet: not run (needs a Slurm cluster and dask_jobqueue) -->

It is still compiled, so a syntax error is caught. Any other
``<!-- snippet: … -->`` comment is an error."""

import os
import pathlib
import re
import signal
import subprocess
import sys

import pytest

from conftest import ROOT

PAGES = sorted([ROOT / "README.md", *(ROOT / "docs").rglob("*.md")])
FENCE = re.compile(r"^(\s*)```\s*(python3?|py)\s*$")
MARK = re.compile(r"^\s*<!--\s*snippet:\s*(.*?)\s*-->\s*$")
NOT_RUN = re.compile(r"^not run \((.{10,})\)$")
TIMEOUT_S = 300


def snippets(text):
    """``(first line number, code, reason it is not run or None)`` of every
    Python block of a Markdown text; raises ValueError on an unclosed block
    or a malformed mark."""
    lines = text.splitlines()
    out = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, start = m.group(1), i + 1
        reason = None
        if i > 0 and (mark := MARK.match(lines[i - 1])):
            nr = NOT_RUN.match(mark.group(1))
            if not nr:
                raise ValueError(f"line {i}: a snippet mark must read '<!-- snippet: not run (the reason) -->', not {lines[i - 1].strip()!r}")
            reason = nr.group(1)
        j = start
        while j < len(lines) and lines[j].strip() != "```":
            j += 1
        if j == len(lines):
            raise ValueError(f"line {start}: a ```python block that is never closed")
        body = [l[len(indent):] if l.startswith(indent) else l for l in lines[start:j]]
        out.append((start + 1, "\n".join(body) + "\n", reason))
        i = j + 1
    return out


def test_the_extractor_finds_what_it_should():
    page = "\n".join([
        "text", "```python", "print(1)", "```", "",
        "<!-- snippet: not run (needs a Slurm cluster here) -->", "```python", "import dask_jobqueue", "```",
        "- item:", "  ```py", "  x = 2", "  ```", "```sh", "echo no", "```",
    ])
    assert snippets(page) == [(3, "print(1)\n", None), (8, "import dask_jobqueue\n", "needs a Slurm cluster here"), (12, "x = 2\n", None)]
    with pytest.raises(ValueError, match="snippet mark"):
        snippets("<!-- snippet: skip -->\n```python\npass\n```\n")
    with pytest.raises(ValueError, match="never closed"):
        snippets("```python\npass\n")


def _all():
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        # An independent count of the fences, so that a block the
        # extractor missed cannot pass unseen.
        fences = sum(1 for l in text.splitlines() if FENCE.match(l))
        got = snippets(text)
        assert len(got) == fences, f"{page}: {fences} fences, {len(got)} snippets"
        for line, code, reason in got:
            found.append(pytest.param(page, line, code, reason, id=f"{page.relative_to(ROOT)}:{line}"))
    return found


SNIPPETS = _all()


def test_the_guide_has_snippets():
    # README.md, docs/python.md (two), docs/cluster.md at least.
    pages = {p.values[0].name for p in SNIPPETS}
    assert len(SNIPPETS) >= 4 and {"README.md", "python.md", "cluster.md"} <= pages, pages


@pytest.mark.parametrize("page,line,code,reason", SNIPPETS)
def test_snippet_runs_as_a_script(tmp_path, page, line, code, reason):
    where = f"{page.relative_to(ROOT)}, line {line}"
    compile(code, where, "exec")
    if reason is not None:
        # Marked: compiled only; the reason is in the page, beside it.
        return
    script = tmp_path / "snippet.py"
    script.write_text(code, encoding="utf-8")
    env = dict(os.environ, MPLBACKEND="Agg")
    # Its own process group: on a timeout, the snippet's worker processes
    # (dask's) go with it.
    p = subprocess.Popen([sys.executable, str(script)], cwd=tmp_path, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = p.communicate(timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, err = p.communicate()
        pytest.fail(f"{where}: still running after {TIMEOUT_S} s (make the snippet smaller)\n--- stderr\n{err}")
    assert p.returncode == 0, f"{where}: exit {p.returncode}\n--- stdout\n{out}\n--- stderr\n{err}"
