#!/usr/bin/env python3
"""A terminal's screen, as `tmux capture-pane -e -p` prints it (text with SGR colours), drawn as a
PNG: each cell's background, then its glyph in its foreground colour — half and quarter blocks as
exact rectangles, everything else in DejaVu Sans Mono. For the README's whole-screen pictures (HUD
and map included), which `mazewalk render --png` (the 3D view's cells only) does not draw.

    tmux capture-pane -e -p -t PANE > screen.txt
    scripts/screen_png.py screen.txt screen.png [COLSxROWS]

Needs Python 3 with Pillow (Debian: python3-pil) and fonts-dejavu-core.
"""

import re
import sys

from PIL import Image, ImageDraw, ImageFont

FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSansMono.ttf"
CELL_W, CELL_H = 10, 20
DEFAULT_FG = (204, 204, 204)
DEFAULT_BG = (0, 0, 0)

# xterm's 16 colours, then the 6x6x6 cube and the greys.
BASE16 = [
    (0, 0, 0), (205, 0, 0), (0, 205, 0), (205, 205, 0), (0, 0, 238), (205, 0, 205), (0, 205, 205),
    (229, 229, 229), (127, 127, 127), (255, 0, 0), (0, 255, 0), (255, 255, 0), (92, 92, 255),
    (255, 0, 255), (0, 255, 255), (255, 255, 255),
]


def palette(n):
    if n < 16:
        return BASE16[n]
    if n < 232:
        n -= 16
        level = lambda v: 0 if v == 0 else 55 + 40 * v
        return (level(n // 36), level(n // 6 % 6), level(n % 6))
    grey = 8 + 10 * (n - 232)
    return (grey, grey, grey)


# Block elements drawn as rectangles: (x0, y0, x1, y1) in halves of the cell.
BLOCKS = {
    "▀": [(0, 0, 2, 1)], "▄": [(0, 1, 2, 2)], "█": [(0, 0, 2, 2)], "▌": [(0, 0, 1, 2)],
    "▐": [(1, 0, 2, 2)], "▘": [(0, 0, 1, 1)], "▝": [(1, 0, 2, 1)], "▖": [(0, 1, 1, 2)],
    "▗": [(1, 1, 2, 2)], "▚": [(0, 0, 1, 1), (1, 1, 2, 2)], "▞": [(1, 0, 2, 1), (0, 1, 1, 2)],
    "▙": [(0, 0, 1, 2), (1, 1, 2, 2)], "▛": [(0, 0, 2, 1), (0, 1, 1, 2)],
    "▜": [(0, 0, 2, 1), (1, 1, 2, 2)], "▟": [(1, 0, 2, 2), (0, 1, 1, 2)],
}

SGR = re.compile(r"\x1b\[([0-9;:]*)m")


def parse(text, cols, rows):
    """The screen's cells: rows of (char, fg, bg)."""
    screen = []
    for line in text.split("\n")[:rows]:
        fg, bg, reverse = DEFAULT_FG, DEFAULT_BG, False
        cells = []
        pos = 0
        for match in SGR.finditer(line + "\x1b[m"):
            for ch in line[pos:match.start()]:
                cells.append((ch, bg, fg) if reverse else (ch, fg, bg))
            pos = match.end()
            params = [int(p) if p else 0 for p in re.split("[;:]", match.group(1))] or [0]
            i = 0
            while i < len(params):
                p = params[i]
                if p == 0:
                    fg, bg, reverse = DEFAULT_FG, DEFAULT_BG, False
                elif p == 7:
                    reverse = True
                elif p == 27:
                    reverse = False
                elif 30 <= p <= 37:
                    fg = palette(p - 30)
                elif 90 <= p <= 97:
                    fg = palette(p - 90 + 8)
                elif 40 <= p <= 47:
                    bg = palette(p - 40)
                elif 100 <= p <= 107:
                    bg = palette(p - 100 + 8)
                elif p == 39:
                    fg = DEFAULT_FG
                elif p == 49:
                    bg = DEFAULT_BG
                elif p in (38, 48) and i + 1 < len(params):
                    if params[i + 1] == 5 and i + 2 < len(params):
                        colour = palette(params[i + 2])
                        i += 2
                    elif params[i + 1] == 2 and i + 4 < len(params):
                        colour = tuple(params[i + 2:i + 5])
                        i += 4
                    else:
                        colour = None
                    if colour is not None:
                        if p == 38:
                            fg = colour
                        else:
                            bg = colour
                i += 1
        cells = cells[:cols]
        cells += [(" ", DEFAULT_FG, DEFAULT_BG)] * (cols - len(cells))
        screen.append(cells)
    while len(screen) < rows:
        screen.append([(" ", DEFAULT_FG, DEFAULT_BG)] * cols)
    return screen


def draw(screen, out):
    rows, cols = len(screen), len(screen[0])
    image = Image.new("RGB", (cols * CELL_W, rows * CELL_H), DEFAULT_BG)
    pen = ImageDraw.Draw(image)
    font = ImageFont.truetype(FONT, 16)
    for r, row in enumerate(screen):
        for c, (ch, fg, bg) in enumerate(row):
            x, y = c * CELL_W, r * CELL_H
            pen.rectangle([x, y, x + CELL_W - 1, y + CELL_H - 1], fill=bg)
            if ch in BLOCKS:
                hw, hh = CELL_W // 2, CELL_H // 2
                for x0, y0, x1, y1 in BLOCKS[ch]:
                    pen.rectangle([x + x0 * hw, y + y0 * hh, x + x1 * hw - 1, y + y1 * hh - 1], fill=fg)
            elif ch != " ":
                pen.text((x, y + 1), ch, font=font, fill=fg)
    image.save(out)


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    text = open(sys.argv[1], encoding="utf-8").read().rstrip("\n")
    if len(sys.argv) == 4:
        cols, rows = (int(n) for n in sys.argv[3].split("x"))
    else:
        lines = text.split("\n")
        cols, rows = max(len(SGR.sub("", l)) for l in lines), len(lines)
    draw(parse(text, cols, rows), sys.argv[2])


if __name__ == "__main__":
    main()
