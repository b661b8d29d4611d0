"""Write files so that nobody ever sees half of one.

Every file the project writes (training views, checkpoints, models, cards, benchmark results,
report pages and charts, presets) goes through :func:`atomic_path`: the data is written to a
temporary file in the target's folder, which is renamed onto the target (``os.replace``, atomic
on POSIX) only once it is complete. On any failure, an interrupt included, the temporary file is
removed and an existing target is left as it was. The C++ writers do the same
(``vtkPTVEXRPassWriter``, ``vtkPTVOpenVDBWriter``).
"""
from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import Iterator, Union

PathLike = Union[str, "os.PathLike[str]"]

# Permissions of a file created normally (mkstemp's are 0600).
_UMASK = os.umask(0)
os.umask(_UMASK)


@contextlib.contextmanager
def atomic_path(path: PathLike, suffix: str = ".tmp") -> Iterator[Path]:
    """Yield a temporary path beside ``path`` to write to; rename it onto ``path`` on success.

    ``suffix`` ends the temporary name (e.g. ``".tmp.png"`` for writers that pick the format
    from the extension). The target's folder is created if needed.
    """
    target = Path(path)
    target.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix, dir=target.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_UMASK)
        os.replace(tmp, target)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_text(path: PathLike, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically; returns the path."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding=encoding)
    return Path(path)


def write_bytes(path: PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (flushed to disk before the rename)."""
    with atomic_path(path) as tmp:
        with open(tmp, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
    return Path(path)
