"""Seeded fuzzing of the data and path readers: every hostile file is read or refused with an
:class:`InputError`, never a traceback of another kind. The same cases run every time; the slow
test runs more of them."""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest

from common.errors import InputError
from paintapp.explore.flow_files import load_flow
from paintapp.explore.probe_paths import read_probe_path

HOSTILE_NUMBERS = ["nan", "inf", "-inf", "1e308", "-1", "0", "99999", "4294967296", "1e30", "x",
                   "", "9" * 40, "-99999"]  # fmt: skip
SHAPES = [(), (0,), (2,), (3,), (100_000, 100_000), (2**40,), (6, 6), (2, 6, 6), (1, 2**31)]


def _npz_bytes(rng: np.random.Generator) -> bytes:
    arrays = {"p": np.zeros((6, 6)), "u": np.zeros((2, 6, 6)), "origin": np.zeros(2),
              "spacing": np.full(2, 0.2), "density": np.array(1.0),
              "viscosity": np.array(1e-3)}  # fmt: skip
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, value in arrays.items():
            buffer = io.BytesIO()
            if rng.random() < 0.3:  # a lying header: a random shape over the real bytes
                shape = SHAPES[rng.integers(len(SHAPES))]
                np.lib.format.write_array_header_1_0(
                    buffer, {"descr": "<f8", "fortran_order": False, "shape": shape}
                )
                buffer.write(value.tobytes())
            else:
                np.save(buffer, value)
            archive.writestr(f"{name}.npy", buffer.getvalue())
    raw = bytearray(out.getvalue())
    for _ in range(rng.integers(0, 4)):  # flip a few bytes
        raw[rng.integers(len(raw))] = rng.integers(256)
    if rng.random() < 0.2:
        raw = raw[: rng.integers(len(raw))]
    return bytes(raw)


def _vti_text(rng: np.random.Generator) -> str:
    def pick(good: str, count: int) -> str:
        if rng.random() < 0.6:
            return good
        return " ".join(HOSTILE_NUMBERS[rng.integers(len(HOSTILE_NUMBERS))] for _ in range(count))

    extent = pick("0 3 0 3 0 0", 6)
    return (
        '<?xml version="1.0"?>\n<VTKFile type="ImageData" version="1.0"><ImageData '
        f'WholeExtent="{extent}" Origin="{pick("0 0 0", 3)}" Spacing="{pick("1 1 1", 3)}">'
        f'<Piece Extent="{extent}"></Piece></ImageData></VTKFile>\n'
    )


def _path_text(rng: np.random.Generator) -> str:
    columns = ["t_s", "x_m", "y_m", "angle_rad", "x_m", "z_m", "w"]
    header = [str(c) for c in rng.choice(columns, rng.integers(1, 5))]
    if rng.random() < 0.5:
        header = ["t_s", "x_m", "y_m"]
    rows = [",".join(header)]
    for _ in range(rng.integers(0, 4)):
        cells = [HOSTILE_NUMBERS[rng.integers(len(HOSTILE_NUMBERS))] for _ in header]
        if rng.random() < 0.1:
            cells[0] = '"' + "1" * 140_000 + '"'
        rows.append(",".join(cells))
    return "\n".join(rows) + "\n"


def _fuzz(tmp_path, seed: int, cases: int) -> None:
    rng = np.random.default_rng(seed)
    for case in range(cases):
        npz = tmp_path / f"f{case}.npz"
        npz.write_bytes(_npz_bytes(rng))
        path = tmp_path / f"p{case}.csv"
        path.write_text(_path_text(rng), encoding="utf-8")
        try:
            load_flow([npz])
        except InputError as exc:
            assert "\n" not in str(exc) and len(str(exc)) < 600
        try:
            read_probe_path(path, 2)
        except InputError as exc:
            assert "\n" not in str(exc) and len(str(exc)) < 600
        vti = tmp_path / f"v{case}.vti"
        vti.write_text(_vti_text(rng), encoding="utf-8")
        if HAVE_VTK:
            try:
                load_flow([vti])
            except InputError as exc:
                assert "\n" not in str(exc) and str(vti) in str(exc)


try:
    import vtkmodules  # noqa: F401

    HAVE_VTK = True
except ImportError:
    HAVE_VTK = False


def test_hostile_data_and_path_files_are_read_or_refused(tmp_path):
    _fuzz(tmp_path, seed=49, cases=40)


@pytest.mark.slow
def test_more_hostile_data_and_path_files_are_read_or_refused(tmp_path):
    _fuzz(tmp_path, seed=4949, cases=400)
