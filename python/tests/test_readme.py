"""The README's Python example runs as written, from the repository's root, and prints the
free-run figures of the model it fits and of its ARX baseline."""

import contextlib
import io
import os
import re


def test_the_readme_python_block_runs(root):
    text = (root / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 1, blocks
    out = io.StringIO()
    cwd = os.getcwd()
    os.chdir(root)
    try:
        with contextlib.redirect_stdout(out):
            exec(compile(blocks[0], "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    printed = out.getvalue()
    # Two lists of per-output figures: the model's, then the baseline's.
    assert printed.count("rms_error") == 2, printed
    rms = [float(x) for x in re.findall(r"'rms_error': ([0-9.e-]+)", printed)]
    assert rms[0] < rms[1], printed
