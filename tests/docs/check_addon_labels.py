#!/usr/bin/env python3
"""The docs name the add-on's buttons as the panel shows them: for every button of
blender_addon/firmament_sky/panels.py with a label of two words or more (its text="...", else its
operator's bl_label), the label's first word never stands in the README or docs/*.md without the
rest ("Generate" for "Generate Sky").  Static: reads the sources, needs no Blender.
Usage: check_addon_labels.py [ROOT]"""
import glob
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "../.."))
ADDON = os.path.join(ROOT, "blender_addon", "firmament_sky")


def button_labels():
    """{label as shown: operator id} for the panels' buttons."""
    bl = {}
    for path in glob.glob(os.path.join(ADDON, "*.py")):
        text = open(path, encoding="utf-8").read()
        for idname, label in re.findall(r'bl_idname = "([\w.]+)"\s*\n\s*bl_label = "([^"]*)"', text):
            bl[idname] = label
    shown = {}
    panels = open(os.path.join(ADDON, "panels.py"), encoding="utf-8").read()
    for idname, args in re.findall(r'\.operator\("([\w.]+)"([^)]*)\)', panels):
        m = re.search(r'text="([^"]*)"', args)
        label = (m.group(1) if m else bl.get(idname, "")).rstrip(".")
        shown[label] = idname
    return {label: op for label, op in shown.items() if len(label.split()) > 1}


def main():
    labels = button_labels()
    bad = []
    docs = [os.path.join(ROOT, "README.md")] + sorted(glob.glob(os.path.join(ROOT, "docs", "*.md")))
    for path in docs:
        text = open(path, encoding="utf-8").read()
        for label in labels:
            first, rest = label.split(None, 1)
            rest = r"\s+".join(re.escape(w) for w in rest.split())  # the label may wrap across lines
            for m in re.finditer(r"\b%s\b(?!\s+%s)" % (re.escape(first), rest), text):
                n = text.count("\n", 0, m.start()) + 1
                bad.append(f"{os.path.relpath(path, ROOT)}:{n}: '{first}' for the button \"{label}\"")
    for b in bad:
        print("FAIL:", b)
    print(f"buttons of two words or more: {', '.join(sorted(labels))}; {len(bad)} misnamed")
    return 1 if bad or not labels else 0


if __name__ == "__main__":
    sys.exit(main())
