#!/usr/bin/env python3
"""Check the relative links of the Markdown files in docs/ (and the READMEs that point into it):
every linked file exists and every #anchor names a heading of its file (GitHub's rule: lower
case, punctuation dropped, spaces to hyphens). Run: python3 tests/docs/check_links.py"""
import os
import re
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FILES = [os.path.join("docs", f) for f in sorted(os.listdir(os.path.join(ROOT, "docs")))
         if f.endswith(".md")] + ["README.md", "examples/scenes/README.md"]


def anchors(path):
    out, fence = set(), False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                fence = not fence
            m = None if fence else re.match(r"#+\s+(.*)", line)
            if m:
                text = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower().replace("`", ""))
                out.add(text.replace(" ", "-"))
    return out


def main():
    errors = []
    for rel in FILES:
        path = os.path.join(ROOT, rel)
        with open(path, encoding="utf-8") as f:
            text = re.sub(r"```.*?```", "", f.read(), flags=re.S)
        for target in re.findall(r"\]\(([^)\s]+)\)", text):
            if re.match(r"[a-z]+:", target):
                continue
            file_part, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) if file_part else path
            if not os.path.exists(dest):
                errors.append("%s: link to a missing file: %s" % (rel, target))
            elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                errors.append("%s: no heading for the anchor: %s" % (rel, target))
    for e in errors:
        print(e)
    print("%d broken links" % len(errors) if errors else "every link of %d files resolves" % len(FILES))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
