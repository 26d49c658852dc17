"""Planning: how a render is cut into parts (pure functions, no Ray, no caustic)."""

import hashlib
import json


def edges(total, pieces):
    """pieces + 1 increasing integers from 0 to total, as even as integers allow."""
    if not 1 <= pieces <= total:
        raise ValueError("cannot cut %d into %d pieces" % (total, pieces))
    return [round(i * total / pieces) for i in range(pieces + 1)]


def grid(tiles, width, height):
    """(columns, rows) with columns * rows == tiles and cells as square as possible."""
    best = None
    for cols in range(1, tiles + 1):
        if tiles % cols:
            continue
        rows = tiles // cols
        if cols > width or rows > height:
            continue
        # The aspect ratio of a cell, 1 for a square; prefer the squarest.
        aspect = (width / cols) / (height / rows)
        score = max(aspect, 1 / aspect)
        if best is None or score < best[0]:
            best = (score, cols, rows)
    if best is None:
        raise ValueError("cannot cut a %dx%d image into %d crops" % (width, height, tiles))
    return best[1], best[2]


class Part:
    """One task of a split render: sample indices [s0, s1) of pixels [x0, x1) x [y0, y1)."""

    def __init__(self, s0, s1, x0, x1, y0, y1, stem):
        self.s0, self.s1, self.x0, self.x1, self.y0, self.y1 = s0, s1, x0, x1, y0, y1
        # The name caustic gives the part file (app/part_file.cpp, partFileName).
        self.name = "%s.part-s%d-%d-x%d-%d-y%d-%d.exr" % (stem, s0, s1, x0, x1, y0, y1)

    @property
    def sample_range(self):
        return "%d:%d" % (self.s0, self.s1)

    @property
    def crop(self):
        return "%d:%d,%d:%d" % (self.x0, self.x1, self.y0, self.y1)

    @property
    def pixel_samples(self):
        return (self.s1 - self.s0) * (self.x1 - self.x0) * (self.y1 - self.y0)


def split_render(stem, width, height, samples, chunks, crop_tiles):
    """The parts of a render: chunks sample ranges x crop_tiles crops, in sample-range order."""
    s = edges(samples, chunks)
    cols, rows = grid(crop_tiles, width, height)
    xs, ys = edges(width, cols), edges(height, rows)
    parts = []
    for i in range(chunks):
        for r in range(rows):
            for c in range(cols):
                parts.append(Part(s[i], s[i + 1], xs[c], xs[c + 1], ys[r], ys[r + 1], stem))
    return parts


def plan_key(*items):
    """A short hash of what decides a plan's parts (scene, flags, sizes), naming its parts folder,
    so that --resume never reuses parts of a different render."""
    text = json.dumps(items, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]
