"""atheris (libFuzzer for Python): arbitrary bytes as an .exr through the training data reader.

``ptv_training.exr_io.read_exr`` must either return channels or raise an ``Exception`` (which the
training loader reports as an unreadable view); ``verify_view_file`` must return ``(False, why)``
and never raise. A crash, hang or unbounded allocation inside OpenEXR is a finding. Run by
``scripts/fuzz.sh``; extra arguments go to libFuzzer.
"""
import os
import sys
import tempfile

import atheris

with atheris.instrument_imports():
    from ptv_training import exr_io

PATH = os.path.join(tempfile.gettempdir(), f"ptv_fuzz_{os.getpid()}.exr")


def test_one_input(data: bytes) -> None:
    with open(PATH, "wb") as f:
        f.write(data)
    try:
        channels, _ = exr_io.read_exr(PATH)
    except Exception:  # noqa: BLE001 -- any error is fine, as long as it is an exception
        channels = None
    if channels is not None:
        for name, values in channels.items():
            assert values.ndim == 2, (name, values.shape)
    ok, why = exr_io.verify_view_file(PATH)
    assert ok or why, "a rejected view must say why"


if __name__ == "__main__":
    atheris.Setup(sys.argv, test_one_input)
    atheris.Fuzz()
