"""caustic's EXR files (images and part files) read with the Academy Software Foundation's OpenEXR
Python bindings (PyPI `OpenEXR`, pinned by setup.sh): the farm checks part files with it before it
keeps or merges them, and the tests read caustic's images with it. Channels keep their full
names ("R", "albedo.R", "sum.A") and the type they are stored in (float32 or float16)."""

import contextlib
import os
import sys


@contextlib.contextmanager
def _library_messages_to_stderr():
    # OpenEXR's bindings print a warning about a damaged file on the process's standard output
    # (its C++ std::cout), where the farm lists the files it wrote: the warning goes to standard
    # error for the time of the read.
    sys.stdout.flush()
    saved = os.dup(1)
    try:
        os.dup2(2, 1)
        yield
    finally:
        sys.stdout.flush()
        os.dup2(saved, 1)
        os.close(saved)


def _open(path, header_only):
    import OpenEXR

    with _library_messages_to_stderr():
        f = OpenEXR.File(path, separate_channels=True, header_only=header_only)
        if not f.parts:   # a file whose pixels could not be read is opened with no part
            raise ValueError("its pixel data cannot be read")
        channels = {} if header_only else {name: c.pixels for name, c in f.channels().items()}
    return f.header(), channels


def _size(header):
    (x0, y0), (x1, y1) = header["dataWindow"]
    return int(x1 - x0 + 1), int(y1 - y0 + 1)


def read_header(path):
    """The header's attributes ({name: value}; caustic's own are strings)."""
    return _open(path, header_only=True)[0]


def read_exr(path):
    """(attributes, width, height, {channel name: numpy array of height x width, row 0 at the
    top}). Raises ValueError for a file that is not a complete OpenEXR image."""
    try:
        header, channels = _open(path, header_only=False)
    except (RuntimeError, ValueError) as e:
        raise ValueError("%s: not a complete OpenEXR file (%s)" % (path, e))
    w, h = _size(header)
    return header, w, h, channels


def check_complete(path):
    """Reads the whole file: (attributes, width, height, channel names, problem or ""), where a
    problem is a file that is not OpenEXR or whose pixels cannot all be read (cut short, damaged)."""
    try:
        header, w, h, channels = read_exr(path)
    except (OSError, ValueError) as e:
        return {}, 0, 0, [], str(e)
    return header, w, h, sorted(channels), ""
