"""caustic-farm: caustic's renders, sweeps and batches as Ray tasks (docs/farm.md).

The farm sits above caustic's command line: a render is split into parts with
``caustic --sample-range`` / ``--crop``, each part is one Ray task, and ``caustic merge`` makes
the image from the part files. Importing this package does not import Ray.
"""

__version__ = "0.1.0"
