#!/usr/bin/env python3
"""Checks that a markdown file's links to headings resolve.

For each file given (default: README.md and BENCHMARKS.md), every link `(#anchor)` must name a
heading of that file, and every link `(OTHER.md#anchor)` to a markdown file beside it must name a
heading of that file. Anchors are GitHub's: the heading's text without its markdown (code ticks,
emphasis, link targets), lowercased, characters other than word characters, spaces and hyphens
dropped, spaces turned to hyphens; a repeated slug gets `-1`, `-2`, ... Fenced code blocks are
skipped. Prints each broken link as FILE:LINE: #anchor and exits 1 if there is any.
Standard library only. Usage: python3 scripts/check_anchors.py [FILE.md ...]
"""

import re
import sys
from pathlib import Path

HEADING = re.compile(r"^ {0,3}(#{1,6})[ \t]+(.*?)[ \t]*#*[ \t]*$")
LINK = re.compile(r"\]\(([^()\s]*?)#([^()\s]*)\)")
FENCE = re.compile(r"^ {0,3}(`{3,}|~{3,})(.*)$")


def lines_outside_fences(text):
    """(line number, line) for the lines not inside a fenced code block. As CommonMark has it: a
    backtick fence's info string holds no backtick, and a closing fence is the opening one's
    character, at least as long, and nothing after it but spaces (so a line of an ascii picture
    that starts with backticks stays inside its block)."""
    fence = None
    for number, line in enumerate(text.splitlines(), 1):
        m = FENCE.match(line)
        if m:
            run, rest = m.group(1), m.group(2)
            if fence is None and not (run[0] == "`" and "`" in rest):
                fence = run
                continue
            if fence is not None and run[0] == fence[0] and len(run) >= len(fence) and not rest.strip():
                fence = None
                continue
        if fence is None:
            yield number, line


def plain(heading):
    """The heading's text as GitHub renders it, without markdown."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links and images: their text
    text = re.sub(r"<[^>]+>", "", text)  # inline HTML tags
    return text.replace("`", "").replace("*", "")


def slug(text):
    text = plain(text).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path):
    seen = {}
    out = set()
    for _, line in lines_outside_fences(path.read_text(encoding="utf-8")):
        m = HEADING.match(line)
        if not m:
            continue
        base = slug(m.group(2))
        n = seen.get(base, 0)
        seen[base] = n + 1
        out.add(base if n == 0 else f"{base}-{n}")
    return out


def main(argv):
    files = [Path(a) for a in argv] or [Path("README.md"), Path("BENCHMARKS.md")]
    cache = {}

    def of(path):
        key = path.resolve()
        if key not in cache:
            cache[key] = anchors(path) if path.is_file() else None
        return cache[key]

    broken = 0
    checked = 0
    for path in files:
        text = path.read_text(encoding="utf-8")
        for number, line in lines_outside_fences(text):
            # Inline code may show link syntax without being a link.
            for m in LINK.finditer(re.sub(r"`[^`]*`", "", line)):
                target, anchor = m.group(1), m.group(2)
                if target == "":
                    dest = path
                elif target.endswith(".md") and "://" not in target:
                    dest = path.parent / target
                else:
                    continue
                checked += 1
                found = of(dest)
                if found is None:
                    print(f"{path}:{number}: {target}#{anchor}: no such file")
                    broken += 1
                elif anchor not in found:
                    print(f"{path}:{number}: {target}#{anchor}")
                    broken += 1
    print(f"{checked} links checked, {broken} broken", file=sys.stderr)
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
