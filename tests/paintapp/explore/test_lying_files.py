"""Data and path files that claim more than they hold are refused before any memory is spent."""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest

from common.errors import InputError
from paintapp.cli import main
from paintapp.explore.flow_files import load_flow

GOOD = {"p": np.zeros((6, 6)), "u": np.zeros((2, 6, 6)), "origin": np.zeros(2),
        "spacing": np.full(2, 0.2), "density": np.array(1.0), "viscosity": np.array(1e-3)}  # fmt: skip


def _npy_header(shape: tuple[int, ...]) -> bytes:
    out = io.BytesIO()
    np.lib.format.write_array_header_1_0(
        out, {"descr": "<f8", "fortran_order": False, "shape": shape}
    )
    return out.getvalue()


def _write_npz(path, members: dict[str, bytes]) -> None:
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, value in GOOD.items():
            if name not in members:
                buffer = io.BytesIO()
                np.save(buffer, value)
                archive.writestr(f"{name}.npy", buffer.getvalue())
        for name, raw in members.items():
            archive.writestr(f"{name}.npy", raw)


@pytest.fixture
def no_inflating(monkeypatch):
    """Fail if the reader gets as far as loading (inflating) the arrays."""

    def refuse(*args, **kwargs):
        raise AssertionError("the arrays were loaded before the headers were checked")

    monkeypatch.setattr(np, "load", refuse)


def test_a_compressed_bomb_member_is_refused_on_its_header(tmp_path, no_inflating):
    path = tmp_path / "bomb.npz"
    _write_npz(path, {"density": _npy_header((4_000_000,)) + bytes(32_000_000)})
    assert path.stat().st_size < 100_000
    with pytest.raises(InputError) as err:
        load_flow([path])
    assert err.value.key == "density" and str(path) in str(err.value)


def test_a_member_compressed_other_than_by_deflate_is_refused_before_any_read(tmp_path):
    # zipfile inflates a bzip2 member without bounding a read's output: even reading its .npy
    # header would inflate the whole member, so such a member is refused from the zip directory
    path = tmp_path / "bzip2.npz"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_BZIP2) as archive:
        archive.writestr("density.npy", _npy_header((4_000_000,)) + bytes(32_000_000))
    opened = []
    original = zipfile.ZipFile.open

    def watch(self, *args, **kwargs):
        opened.append(args[0])
        return original(self, *args, **kwargs)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(zipfile.ZipFile, "open", watch)
        with pytest.raises(InputError, match="deflate") as err:
            load_flow([path])
    assert err.value.key == "density" and opened == []


def test_an_array_header_beyond_the_memory_budget_is_refused(tmp_path, no_inflating):
    path = tmp_path / "huge.npz"
    _write_npz(path, {"p": _npy_header((100_000, 100_000))})
    with pytest.raises(InputError, match="bytes are read") as err:
        load_flow([path])
    assert err.value.key == "p" and str(path) in str(err.value)


def test_a_plain_npy_named_npz_is_refused(tmp_path):
    path = tmp_path / "plain.npz"
    with open(path, "wb") as fh:
        np.save(fh, np.zeros(3))
    with pytest.raises(InputError, match=r"not a readable \.npz"):
        load_flow([path])


def test_a_folder_is_not_a_missing_file(tmp_path):
    with pytest.raises(InputError, match="is a folder"):
        load_flow([tmp_path])


VTI = (
    '<?xml version="1.0"?>\n<VTKFile type="ImageData" version="1.0"><ImageData '
    'WholeExtent="{extent}" Origin="{origin}" Spacing="{spacing}">'
    '<Piece Extent="{extent}"></Piece></ImageData></VTKFile>\n'
)


@pytest.mark.parametrize(
    ("name", "text", "key"),
    [
        ("big.vti", VTI.format(extent="0 99999 0 99999 0 0", origin="0 0 0", spacing="1 1 1"),
         "WholeExtent"),
        ("nan.vti", VTI.format(extent="0 3 0 3 0 0", origin="0 0 0", spacing="nan nan nan"),
         "Spacing"),
        ("inf.vti", VTI.format(extent="0 3 0 3 0 0", origin="inf 0 0", spacing="1 1 1"), "Origin"),
        ("big.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\n"
         "DIMENSIONS 100000 100000 1\nORIGIN 0 0 0\nSPACING 1 1 1\n", "DIMENSIONS"),
        ("nan.vtk", "# vtk DataFile Version 3.0\nx\nASCII\nDATASET STRUCTURED_POINTS\n"
         "DIMENSIONS 3 3 1\nORIGIN 0 0 0\nSPACING nan 1 1\n", "SPACING"),
    ],
)  # fmt: skip
def test_vtk_headers_are_checked_before_vtk_reads(tmp_path, name, text, key):
    pytest.importorskip("vtkmodules")
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InputError) as err:
        load_flow([path])
    assert err.value.key == key and str(path) in str(err.value)


@pytest.fixture
def flow_file(tmp_path):
    path = tmp_path / "f.npz"
    np.savez(path, **GOOD)
    return path


@pytest.mark.parametrize(
    ("path_text", "message"),
    [
        ("t_s,x_m,y_m,x_m\n0,0.5,0.5,0.5\n", "'x_m': column given twice"),
        ('t_s,x_m,y_m\n"' + "1" * 140_000 + '",0,0\n', "line 2: not valid CSV"),
        ("t_s,x_m,y_m\n0,0.5,0.5\n9000,0.5,0.5\n", "'t_s': the path lasts 9000 s"),
    ],
)
def test_a_path_that_asks_too_much_is_refused(tmp_path, capsys, flow_file, path_text, message):
    (tmp_path / "p.csv").write_text(path_text, encoding="utf-8")
    args = ["explore", str(flow_file), "--path", str(tmp_path / "p.csv"),
            "--forces", str(tmp_path / "o.csv")]  # fmt: skip
    assert main(args) == 2
    err = capsys.readouterr().err
    assert message in err and "p.csv" in err and "Traceback" not in err
    assert not (tmp_path / "o.csv").exists()


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--size", "1e4"], "larger than the data set"),
        (["--size", "1e300"], "larger than the data set"),
        (["--probe", "box", "--size", "0.1", "0.1", "0.1"], "needs 1 or 2 sizes"),
    ],
)
def test_a_probe_the_data_cannot_hold_is_refused(tmp_path, capsys, flow_file, extra, message):
    (tmp_path / "p.csv").write_text("t_s,x_m,y_m\n0,0.5,0.5\n", encoding="utf-8")
    assert main(["explore", str(flow_file), "--path", str(tmp_path / "p.csv"), *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and "'--size'" in err and "Traceback" not in err
