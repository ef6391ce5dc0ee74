"""A contact sheet: square images on a grid, each scaled to TILE pixels and labelled below.

  contact_sheet.py OUT.png COLUMNS TILE IMAGE=LABEL ...

Written to a temporary name beside OUT.png and renamed when complete (Debian's python3-pil)."""

import os
import sys

from PIL import Image, ImageDraw, ImageFont

LABEL_PX = 22  # the strip under each tile


def font(size):
    for name in ("DejaVuSans.ttf", "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"):
        try:
            return ImageFont.truetype(name, size)
        except OSError:
            pass
    return ImageFont.load_default()


def main(argv):
    if len(argv) < 4:
        raise SystemExit("usage: contact_sheet.py OUT.png COLUMNS TILE IMAGE=LABEL ...")
    out, columns, tile = argv[0], int(argv[1]), int(argv[2])
    items = [a.rsplit("=", 1) for a in argv[3:]]
    rows = (len(items) + columns - 1) // columns
    sheet = Image.new("RGB", (columns * tile, rows * (tile + LABEL_PX)), (0, 0, 0))
    draw = ImageDraw.Draw(sheet)
    f = font(max(10, LABEL_PX - 8))
    for i, (path, label) in enumerate(items):
        x, y = (i % columns) * tile, (i // columns) * (tile + LABEL_PX)
        with Image.open(path) as im:
            sheet.paste(im.convert("RGB").resize((tile, tile), Image.LANCZOS), (x, y))
        w = draw.textlength(label, font=f)
        draw.text((x + (tile - w) / 2, y + tile + 3), label, fill=(220, 220, 220), font=f)
    tmp = out + ".tmp.png"
    sheet.save(tmp, optimize=True)
    os.replace(tmp, out)


if __name__ == "__main__":
    main(sys.argv[1:])
