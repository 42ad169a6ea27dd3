"""Reads every plot of a `subtgraph stats` report folder as a person's tools would: each SVG
must parse as XML with an <svg> root, a title and labels; each PNG must open with Pillow, have
the size its SVG says (twice, as drawn at 2x), and show more than a blank page.

    stats_report.py REPORT_DIR
Prints the number of plots checked."""
import os
import sys
import xml.etree.ElementTree as ET

from PIL import Image

SVG = "{http://www.w3.org/2000/svg}"


def main(folder: str) -> None:
    checked = 0
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".svg"):
            continue
        root = ET.parse(os.path.join(folder, name)).getroot()
        assert root.tag == SVG + "svg", (name, root.tag)
        texts = [t.text for t in root.iter(SVG + "text")]
        assert len(texts) >= 3, (name, texts)
        width, height = float(root.get("width")), float(root.get("height"))
        png = os.path.join(folder, name[:-4] + ".png")
        with Image.open(png) as im:
            im.load()
            assert im.size == (round(width * 2), round(height * 2)), (png, im.size)
            colours = im.convert("RGB").getcolors(maxcolors=1 << 20)
            assert colours is None or len(colours) > 3, (png, "blank")
        checked += 1
    assert checked > 0, "no plots"
    print(checked)


if __name__ == "__main__":
    main(sys.argv[1])
