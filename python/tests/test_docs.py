"""Every ```python snippet of README.md's "From Python" section and of docs/python.md
runs, in order, from the repository's root."""

import os
import re

import pytest


def snippets(text):
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


@pytest.mark.parametrize("doc", ["README.md", "docs/python.md"])
def test_snippets_run(root, doc):
    text = (root / doc).read_text()
    if doc == "README.md":
        text = text.split("## From Python", 1)[1].split("\n## ", 1)[0]
    blocks = snippets(text)
    assert blocks, f"no python snippets in {doc}"
    cwd = os.getcwd()
    os.chdir(root)
    namespace = {}
    try:
        for block in blocks:
            exec(compile(block, doc, "exec"), namespace)
    finally:
        os.chdir(cwd)
