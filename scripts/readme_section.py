# SPDX-License-Identifier: Apache-2.0
"""Rewrites a generated section of README.md (or of another markdown file: `path`, relative to
the repository): the lines between `<!-- BEGIN <name>` (rest of that line free) and
`<!-- END <name> -->`, written through a temporary file so that a failed run leaves the file
whole."""
import os

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def replace_readme_section(name, text, path="README.md"):
    readme = os.path.join(ROOT, path)
    with open(readme) as f:
        content = f.read()
    begin = content.index("\n", content.index(f"<!-- BEGIN {name}")) + 1
    end = content.index(f"<!-- END {name} -->")
    with open(readme + ".tmp", "w") as f:
        f.write(content[:begin] + text + "\n" + content[end:])
    os.replace(readme + ".tmp", readme)
