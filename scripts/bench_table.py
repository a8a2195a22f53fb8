#!/usr/bin/env python3
"""Turns the last `cargo bench` results into the markdown tables of BENCHMARKS.md.

Reads criterion's `target/criterion/**/new/{benchmark,estimates}.json` (medians), the counts the render
bench saves (`render-stats.tsv`) and the byte tables the encoder bench saves (`encoder-bytes.md`).
Standard library only. Usage: python3 scripts/bench_table.py [TARGET_DIR] > tables.md
"""

import csv
import json
import sys
from pathlib import Path

target = Path(sys.argv[1] if len(sys.argv) > 1 else "target")
root = target / "criterion"


def load():
    """full_id -> (median ns, throughput elements or None)."""
    out = {}
    for bench in root.glob("**/new/benchmark.json"):
        meta = json.loads(bench.read_text())
        est = json.loads((bench.parent / "estimates.json").read_text())
        elements = (meta.get("throughput") or {}).get("Elements")
        out[meta["full_id"]] = (est["median"]["point_estimate"], elements)
    return out


def ms(ns):
    return f"{ns / 1e6:.3f}" if ns < 1e9 else f"{ns / 1e9:.2f} s"


def table_head(title, text_columns, number_columns):
    """A markdown table's title, header and alignment rows: text columns left, number columns right."""
    print(f"### {title}\n")
    print("| " + " | ".join(text_columns + number_columns) + " |")
    print("|" + "---|" * len(text_columns) + "--:|" * len(number_columns))


def render_tables(results):
    stats = {}
    stats_file = root / "render-stats.tsv"
    if stats_file.exists():
        with stats_file.open() as f:
            for row in csv.DictReader(f, delimiter="\t"):
                stats[(row["view"], row["maze"], row["charset"], row["size"], row["culling"])] = row
    cases = sorted(
        {tuple(k.split("/")[1:5]) for k in results if k.startswith("render/")},
        key=lambda c: (c[0], c[2], int(c[3].split("x")[0]), int(c[1].split("x")[0])),
    )
    if not cases:
        return
    table_head("Render time per frame (median, ms)", ["view", "charset", "size", "maze"],
               ["portal", "brute force", "brute ÷ portal", "visits / distinct cells",
                "walls drawn (portal / brute)", "wall samples"])
    for view, maze, charset, size in cases:
        base = f"render/{view}/{maze}/{charset}/{size}"
        portal = results.get(base + "/portal", (None,))[0]
        brute = results.get(base + "/none", (None,))[0]
        s = stats.get((view, maze, charset, size, "portal"), {})
        sb = stats.get((view, maze, charset, size, "none"), {})
        ratio = "–"
        if portal and brute:
            r = brute / portal
            ratio = f"{r:.1f}×" if r < 10 else f"{r:.0f}×"
        print(f"| {view} | {charset} | {size} | {maze} | {ms(portal) if portal else '–'} "
              f"| {ms(brute) if brute else '–'} | {ratio} "
              f"| {s.get('cells_visited', '?')} / {s.get('distinct_cells', '?')} "
              f"| {s.get('walls_drawn', '?')} / {sb.get('walls_drawn', '?')} | {s.get('samples_written', '?')} |")
    print()
    table_head("Portal-pass frame time, 1000×1000 and 100×100 ÷ 10×10 (like views)",
               ["view", "charset", "size"], ["10×10", "100×100", "1000×1000", "100² ÷ 10²", "1000² ÷ 10²"])
    for view, charset, size in sorted({(c[0], c[2], c[3]) for c in cases},
                                      key=lambda c: (c[0], c[1], int(c[2].split("x")[0]))):
        t = [results.get(f"render/{view}/{m}/{charset}/{size}/portal", (None,))[0]
             for m in ("10x10", "100x100", "1000x1000")]
        if None in t:
            continue
        print(f"| {view} | {charset} | {size} | {ms(t[0])} | {ms(t[1])} | {ms(t[2])} "
              f"| {t[1] / t[0]:.2f} | {t[2] / t[0]:.2f} |")
    print()


def breakdown_table(results):
    keys = sorted(k for k in results if k.startswith("breakdown/"))
    if not keys:
        return
    table_head("Where a 200×60 frame's time goes (median, ms)", ["view", "maze", "charset"],
               ["portal pass", "samples (all but glyphs)", "glyphs, truecolor", "glyphs, 256"])
    groups = sorted({tuple(k.split("/")[1:5]) for k in keys})
    for view, maze, charset, size in groups:
        base = f"breakdown/{view}/{maze}/{charset}/{size}/"
        cell = lambda name: ms(results[base + name][0]) if base + name in results else "–"
        print(f"| {view} | {maze} | {charset} | {cell('portal_pass')} | {cell('render_samples')} "
              f"| {cell('to_frame_TrueColor')} | {cell('to_frame_Ansi256')} |")
    print()


def encoder_tables(results):
    keys = sorted(k for k in results if k.startswith("encode-walk/"))
    if keys:
        table_head("Encoder time per frame over the walk (median, µs)", ["colours"],
                   ["mazewalk exact", "mazewalk ±1 (default)", "ratatui (diff + crossterm)", "full repaint",
                    "frames"])
        for depth in sorted({k.split("/")[1] for k in keys}):
            row = []
            frames = None
            for name in ("mazewalk", "mazewalk_tolerant", "ratatui", "full_repaint"):
                median, elements = results.get(f"encode-walk/{depth}/{name}", (None, None))
                frames = elements or frames
                row.append(f"{median / elements / 1e3:.1f}" if median and elements else "–")
            print(f"| {depth} | {' | '.join(row)} | {frames} |")
        print()
    md = root / "encoder-bytes.md"
    if md.exists():
        print("### Encoder bytes per frame over the walk\n")
        print(md.read_text())


def maze_table(results):
    keys = sorted(k for k in results if k.startswith("maze-"))
    if not keys:
        return
    table_head("Maze generation and loading (median)", ["benchmark"], ["time"])
    for k in keys:
        ns = results[k][0]
        print(f"| {k} | {ns / 1e6:.0f} ms |" if ns < 1e9 else f"| {k} | {ns / 1e9:.2f} s |")
    print()


results = load()
render_tables(results)
breakdown_table(results)
encoder_tables(results)
maze_table(results)
