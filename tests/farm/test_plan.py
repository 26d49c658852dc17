"""The farm's planning (app/farm/caustic_farm/plan.py): a render cut into parts covers every
sample of every pixel exactly once, crops as square as the tile count allows, names as caustic
gives them. Standard library only; run by ctest as "farm: plan"."""

import os
import sys
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "app", "farm"))
from caustic_farm import plan  # noqa: E402


class Plan(unittest.TestCase):
    def test_every_pixel_sample_is_in_exactly_one_part(self):
        for w, h, n, chunks, tiles in [(40, 24, 16, 4, 2), (7, 5, 3, 3, 6), (1, 1, 1, 1, 1), (33, 17, 100, 7, 4),
                                       (16, 16, 32, 32, 1)]:
            parts = plan.split_render("s", w, h, n, chunks, tiles)
            self.assertEqual(len(parts), chunks * tiles)
            count = {}
            for p in parts:
                self.assertTrue(0 <= p.s0 < p.s1 <= n and 0 <= p.x0 < p.x1 <= w and 0 <= p.y0 < p.y1 <= h)
                for x in range(p.x0, p.x1):
                    for y in range(p.y0, p.y1):
                        for s in range(p.s0, p.s1):
                            count[(x, y, s)] = count.get((x, y, s), 0) + 1
            self.assertEqual(len(count), w * h * n)
            self.assertEqual(set(count.values()), {1})
            self.assertEqual(sum(p.pixel_samples for p in parts), w * h * n)

    def test_edges_and_grids(self):
        self.assertEqual(plan.edges(16, 4), [0, 4, 8, 12, 16])
        self.assertEqual(plan.edges(10, 3), [0, 3, 7, 10])
        self.assertEqual(plan.grid(2, 40, 24), (2, 1))     # two crops of a wide image: side by side
        self.assertEqual(plan.grid(2, 24, 40), (1, 2))
        self.assertEqual(plan.grid(4, 64, 64), (2, 2))
        self.assertEqual(plan.grid(6, 7, 5), (3, 2))
        for bad in [(16, 0), (4, 5)]:
            with self.assertRaises(ValueError):
                plan.edges(*bad)
        with self.assertRaises(ValueError):
            plan.grid(7, 3, 2)   # 7 crops of 3x2 pixels: no grid fits

    def test_names_are_caustics(self):
        (p,) = plan.split_render("out/cornell-box", 40, 24, 16, 1, 1)
        self.assertEqual(p.name, "out/cornell-box.part-s0-16-x0-40-y0-24.exr")   # app/part_file.cpp
        self.assertEqual((p.sample_range, p.crop), ("0:16", "0:40,0:24"))
        self.assertNotEqual(plan.plan_key("a", [1]), plan.plan_key("a", [2]))


if __name__ == "__main__":
    unittest.main()
