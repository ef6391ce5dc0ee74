#!/usr/bin/env python3
"""Every relative link of the README and of docs/ resolves: the file exists and, for a link to a
heading (file.md#heading or #heading), the heading is there (GitHub's anchors: lower case, spaces
to '-', punctuation dropped).  Links in code are not links.  And every decision record in
docs/decisions/ has its line in that folder's index (README.md), and the table of docs/performance/README.md
holds every file there (linked) and names no other unless it says "no run recorded yet".
Usage: check_links.py [ROOT]"""
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


def performance_list():
    """What is wrong with docs/performance/README.md's table of the files there."""
    folder = os.path.join(ROOT, "docs", "performance")
    present = {n for n in os.listdir(folder) if n.endswith(".md") and n != "README.md"}
    listed, bad = set(), []
    for row in open(os.path.join(folder, "README.md"), encoding="utf-8").read().splitlines():
        cell = row.split("|")[1].strip() if row.startswith("| ") else ""
        m = re.fullmatch(r"\[([\w.-]+\.md)\]\(\1\)|`([\w.-]+\.md)` \(no run recorded yet\)", cell)
        if cell and cell != "file" and not m:
            bad.append(f"docs/performance/README.md: '{cell}' is neither a link nor 'NAME (no run recorded yet)'")
        elif m and m.group(1):
            listed.add(m.group(1))
        elif m and m.group(2) in present:
            bad.append(f"docs/performance/README.md: {m.group(2)} exists: link it")
        elif m:
            listed.add(m.group(2))
    bad += [f"docs/performance/{n}: not in docs/performance/README.md" for n in sorted(present - listed)]
    return bad


def main():
    bad, count = [], 0
    bad += [f"docs/decisions/{n}: not in the index (docs/decisions/README.md)" for n in unindexed_decisions()]
    bad += performance_list()
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
