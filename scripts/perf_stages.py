#!/usr/bin/env python3
"""A served frame's time by part, from `perf record` of `mazewalk serve` by the clock (BENCHMARKS.md).

    target/release/examples/load --idle 0 --walkers 60 --rate 30 --seconds 15 &
    sleep 20   # the players in and walking
    perf record -e cpu-clock -F 999 -p "$(pgrep -x mazewalk)" -o serve.perf -- sleep 10
    scripts/perf_stages.py serve.perf

Where callgrind counts instructions (`scripts/callgrind_stages.py`), this weighs the server's time as
the clock does: cache misses, the allocator touching cold memory, the kernel's share of the sockets
and the wake-ups. Each sample goes to the part its function belongs to (by its own time: a function's
callees are their own parts; `memcpy` is its own part, whoever calls it). Prints a markdown table,
in percent of the server's samples.
"""

import re
import subprocess
import sys

# (part, pattern matched against "dso symbol"): the first that matches takes the sample.
PARTS = [
    ("render (`mazewalk_render`)", r"mazewalk_render"),
    ("encoder (`mazewalk_term`)", r"mazewalk_term"),
    ("the walk's HUD, map and `Session` (`mazewalk_walk`)", r"mazewalk_walk"),
    ("the maze and the math (`mazewalk_maze`, `mazewalk_math`)", r"mazewalk_maze|mazewalk_math"),
    ("serve (`mazewalk_serve`)", r"mazewalk_serve"),
    ("`memcpy`, `memmove`, `memset`", r"mem(move|cpy|set)"),
    ("the allocator (`malloc`, `free`)", r"malloc|free|_int_|unlink_chunk|consolidate|realloc|calloc"),
    ("SSH cipher (ring)", r"\bring\b|chacha|poly1305|ChaCha|Poly1305"),
    ("russh", r"russh"),
    ("tokio", r"tokio"),
    ("the kernel", r"\[k\]|\[kernel"),
]


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    text = subprocess.run(
        ["perf", "report", "-i", sys.argv[1], "--no-children", "--sort", "dso,symbol", "--stdio", "-g", "none"],
        check=True, capture_output=True, text=True,
    ).stdout
    shares = {name: 0.0 for name, _ in PARTS}
    shares["everything else"] = 0.0
    for line in text.splitlines():
        m = re.match(r"\s*([\d.]+)%\s+(\S+)\s+(.*)", line)
        if not m or line.startswith("#"):
            continue
        share, what = float(m.group(1)), f"{m.group(2)} {m.group(3)}"
        part = next((name for name, pattern in PARTS if re.search(pattern, what)), "everything else")
        shares[part] += share
    print(f"| part | `{sys.argv[1]}` (% of the server's time) |")
    print("|---|--:|")
    for name, share in shares.items():
        print(f"| {name} | {share:.1f} |")


if __name__ == "__main__":
    main()
