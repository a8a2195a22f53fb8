#!/usr/bin/env python3
"""A served frame's cost by stage, from a callgrind profile of `mazewalk serve` (BENCHMARKS.md).

    valgrind --tool=callgrind --callgrind-out-file=cg.out target/release/mazewalk serve ...
    scripts/callgrind_stages.py cg.out [more.out ...]

Prints, per frame drawn (calls of `Renderer::render`: a HUD-only clock tick encodes without drawing),
the inclusive instruction counts of each stage,
and the frames and looks counted. The work a process does once (the players' start places, each
surface's colour ramps) is counted apart, and the whole process without it: a short run spreads it
over its few hundred frames. Several files: one column each (an A/B in one table).
"""

import os
import re
import subprocess
import sys

# Functions that run once a process (or once a colour ramp), whatever the frames: a short run's
# per-frame figures carry them, spread over its frames.
ONCE = ["mazewalk_serve::spawn::Spawns::new", "mazewalk_render::palette::LightRamp::of_surface"]

# (stage, function names whose inclusive counts are summed): the functions of the project and of russh
# and ring that each stage runs under, as callgrind names them.
STAGES = [
    ("whole process", None),
    ("whole process but the work done once", "steady"),
    ("player task: `Session::frame`", ["mazewalk_walk::session::Session::frame"]),
    ("render (`Renderer::render`)", ["mazewalk_render::pipeline::Renderer::render"]),
    ("portal pass", ["mazewalk_render::portal::PortalPass::run"]),
    ("raster (polygon fills)", ["mazewalk_render::raster::fill_polygon_x8", "mazewalk_render::raster::fill_polygon"]),
    # (`samples_with` is named either way, as rustc's symbol for it has varied between builds.)
    ("samples: portal, raster, shading", ["mazewalk_render::pipeline::Renderer::samples_with",
                                          "mazewalk_render::<impl mazewalk_render::pipeline::Renderer>::samples_with"]),
    ("figures (sprites)", ["mazewalk_render::sprite::SpritePass::draw"]),
    ("glyphs (`glyph::to_frame_faced`)", ["mazewalk_render::glyph::to_frame_faced"]),
    # (`draw_into` since the kept frame of `draw_kept`; `draw` before)
    ("screen: render + HUD + map + colours", ["mazewalk_walk::screen::draw", "mazewalk_walk::screen::draw_into"]),
    # (`encode` and `encode_rows` call `encode_cells`, the clock tick's entry since `encode_rows`
    # was, and are mostly inlined into their callers: the first callgrind name present gives the
    # whole encoder, ticks included.)
    ("encoder (`Encoder::encode_cells`)", ["mazewalk_term::encoder::Encoder::encode_cells",
                                           "mazewalk_term::encoder::Encoder::encode_rows",
                                           "mazewalk_term::encoder::Encoder::encode"]),
    (
        "SSH cipher (ring ChaCha20-Poly1305)",
        [
            "ring::aead::chacha20_poly1305_openssh::SealingKey::seal_in_place",
            "ring::aead::chacha20_poly1305_openssh::OpeningKey::open_in_place",
            "ring::aead::chacha20_poly1305_openssh::OpeningKey::decrypt_packet_length",
        ],
    ),
    ("key exchanges (logins)", ["<russh::kex::KexAlgorithm as russh::kex::KexAlgorithmImplementor>::server_dh"]),
    ("world: looks", ["mazewalk_serve::world::World::look"]),
    ("world: moves", ["mazewalk_serve::world::World::moved", "mazewalk_serve::world::World::pitched"]),
    # Once a process, spread over the frames of a short run: the players' start places, and each
    # surface's colour ramps, built on first use.
    ("once: start places (`Spawns::new`)", ONCE[:1]),
    ("once: ramps built (`LightRamp::of_surface`)", ONCE[1:]),
]
COUNTED = ["mazewalk_render::pipeline::Renderer::render", "mazewalk_term::encoder::Encoder::encode_cells",
           "mazewalk_term::encoder::Encoder::encode_rows",
           "mazewalk_serve::world::World::look", "mazewalk_walk::session::Session::frame"]
# Stages whose names are alternatives (one nests the other): the first one present counts.
FIRST_OF = {"encoder (`Encoder::encode_cells`)"}


def inclusive(path):
    """Function name -> inclusive instructions (functions of the binary, not inlined attributions)."""
    text = subprocess.run(
        ["callgrind_annotate", "--inclusive=yes", "--threshold=100", os.path.abspath(path)],
        # Away from the sources: inside the tree it splits a function's inclusive count by file.
        cwd="/", check=True, capture_output=True, text=True,
    ).stdout
    costs = {}
    for line in text.splitlines():
        m = re.match(r"\s*([\d,]+) \([^)]*\)\s+\S*?:(.*) \[[^\]]+\]$", line)
        if m:
            name = m.group(2)
            costs[name] = max(costs.get(name, 0), int(m.group(1).replace(",", "")))
        m = re.match(r"\s*([\d,]+) \([^)]*\)\s+PROGRAM TOTALS", line)
        if m:
            costs[None] = int(m.group(1).replace(",", ""))
    return costs


def calls(path):
    """Function name -> calls, summed over every call site."""
    names, counts, cfn = {}, {}, None
    with open(path) as f:
        for line in f:
            m = re.match(r"(c?fn)=\((\d+)\)(?: (.*))?", line)
            if m:
                if m.group(3):
                    names[m.group(2)] = m.group(3).strip()
                if m.group(1) == "cfn":
                    cfn = m.group(2)
            elif line.startswith("calls="):
                name = names.get(cfn)
                counts[name] = counts.get(name, 0) + int(line[6:].split()[0])
    return counts


def main():
    paths = sys.argv[1:]
    if not paths:
        sys.exit(__doc__)
    columns = []
    for path in paths:
        costs, counted = inclusive(path), calls(path)
        frames = max(counted.get(COUNTED[0], 0), 1)
        columns.append((costs, counted, frames))
    print("| stage | " + " | ".join(f"`{p}` (k instr./frame)" for p in paths) + " |")
    print("|---|" + "--:|" * len(paths))
    for stage, names in STAGES:
        cells = []
        for costs, _, frames in columns:
            if names is None:
                total = costs.get(None, 0)
            elif names == "steady":
                total = costs.get(None, 0) - sum(costs.get(n, 0) for n in ONCE)
            elif stage in FIRST_OF:
                total = next((costs[n] for n in names if n in costs), 0)
            else:
                total = sum(costs.get(n, 0) for n in names)
            cells.append(f"{total / frames / 1e3:,.0f}")
        print(f"| {stage} | " + " | ".join(cells) + " |")
    for name in COUNTED:
        print(f"| calls of `{name.rsplit('::', 2)[-2]}::{name.rsplit('::', 1)[-1]}` | "
              + " | ".join(f"{c.get(name, 0):,}" for _, c, _ in columns) + " |")


if __name__ == "__main__":
    main()
