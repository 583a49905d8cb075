"""Pixel statistics of a screenshot: the fraction of pixels that differ from the
background colour and the number of distinct colours. Prints 'fraction distinct'."""
import sys

from PIL import Image

img = Image.open(sys.argv[1]).convert("RGB")
w, h = img.size
px = img.load()
bg = (11, 14, 20)  # the viewer's clear colour #0b0e14
differ = 0
colours = set()
for y in range(0, h, 2):
    for x in range(0, w, 2):
        p = px[x, y]
        colours.add(p)
        if max(abs(p[0] - bg[0]), abs(p[1] - bg[1]), abs(p[2] - bg[2])) > 12:
            differ += 1
print(f"{differ / ((w // 2) * (h // 2)):.4f} {len(colours)}")
