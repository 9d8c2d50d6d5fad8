#!/usr/bin/env python3
"""Check the relative links of the Markdown files in docs/ (and the READMEs that point into it):
every linked file exists and every #anchor names a heading of its file (GitHub's rule: lower
case, punctuation dropped, spaces to hyphens). Also check that every section of docs/7dof.md
cited in the tracked files ("docs/7dof.md §2.5", "7dof.md sec. 6.2", "spec §4" in files that
name 7dof.md; "§7.3.N" is item N of §7.3) is a heading there. Run: python3 tests/docs/check_links.py"""
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


def dof_citations():
    """Sections of docs/7dof.md cited by the tracked files that it does not have."""
    import subprocess
    with open(os.path.join(ROOT, "docs", "7dof.md"), encoding="utf-8") as f:
        text = f.read()
    sections = set(re.findall(r"^#+ (\d+(?:\.\d+)?)\.? ", text, re.M))
    items_73 = len(re.findall(r"^\d+\. ", text.split("### 7.3", 1)[-1].split("\n## ", 1)[0], re.M))
    try:
        files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True,
                               check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        return []  # not a git checkout: nothing to list
    cite = re.compile(r"(7dof\.md|spec),? ?(?:§|sec\. |section )?(\d+(?:\.\d+)*)")
    missing = []
    for rel in files:
        path = os.path.join(ROOT, rel)
        if not os.path.isfile(path) or rel.startswith("docs/"):
            continue
        try:
            with open(path, encoding="utf-8") as f:
                body = f.read()
        except UnicodeDecodeError:
            continue
        if "7dof.md" not in body:
            continue
        for line_no, line in enumerate(body.splitlines(), 1):
            for m in cite.finditer(line):
                if m.group(1) == "spec" and "§" not in m.group(0):
                    continue
                number = m.group(2).rstrip(".")
                parts = number.split(".")
                if len(parts) == 3 and parts[:2] == ["7", "3"]:
                    ok = 1 <= int(parts[2]) <= items_73
                else:
                    ok = number in sections
                if not ok:
                    missing.append("%s:%d: cites 7dof.md section %s, which docs/7dof.md does not "
                                   "have" % (rel, line_no, number))
    return missing


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
    errors += dof_citations()
    for e in errors:
        print(e)
    print("%d broken links" % len(errors) if errors else "every link of %d files resolves" % len(FILES))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
