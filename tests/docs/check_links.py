#!/usr/bin/env python3
"""Every relative link of the README and of docs/ resolves: the file exists and, for a link to a
heading (file.md#heading or #heading), the heading is there (GitHub's anchors: lower case, spaces
to '-', punctuation dropped).  Links in code are not links.  And every decision record in
docs/decisions/ has its line in that folder's index (README.md).  Usage: check_links.py [ROOT]"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "../.."))
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def prose(text):
    """The text without fenced code blocks and inline code."""
    text = re.sub(r"^```.*?^```", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


def anchors(path):
    found = set()
    for line in open(path, encoding="utf-8").read().split("\n"):
        m = re.match(r"^#+\s+(.*?)\s*#*$", line)
        if m:
            slug = re.sub(r"[^\w\- ]", "", m.group(1).strip().lower()).replace(" ", "-")
            found.add(slug)
    return found


def files():
    yield os.path.join(ROOT, "README.md")
    for top, dirs, names in os.walk(os.path.join(ROOT, "docs")):
        for n in sorted(names):
            if n.endswith(".md"):
                yield os.path.join(top, n)


def unindexed_decisions():
    """The decision records that docs/decisions/README.md does not link."""
    folder = os.path.join(ROOT, "docs", "decisions")
    linked = set(LINK.findall(prose(open(os.path.join(folder, "README.md"), encoding="utf-8").read())))
    return [n for n in sorted(os.listdir(folder)) if re.match(r"\d{4}-\d\d-\d\d-.*\.md$", n) and n not in linked]


def main():
    bad, count = [], 0
    bad += [f"docs/decisions/{n}: not in the index (docs/decisions/README.md)" for n in unindexed_decisions()]
    for path in files():
        for target in LINK.findall(prose(open(path, encoding="utf-8").read())):
            if re.match(r"[a-z]+:", target):
                continue
            count += 1
            file, _, anchor = target.partition("#")
            dest = os.path.normpath(os.path.join(os.path.dirname(path), file)) if file else path
            where = os.path.relpath(path, ROOT)
            if not os.path.exists(dest):
                bad.append(f"{where}: {target}: no such file")
            elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
                bad.append(f"{where}: {target}: no heading '{anchor}' in {os.path.relpath(dest, ROOT)}")
    for b in bad:
        print("FAIL:", b)
    print(f"{count - len(bad)} links resolve, {len(bad)} do not")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
