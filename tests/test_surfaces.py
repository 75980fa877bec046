"""3D surfaces of states (shellbvp.surface), their pictures and animations
(shellbvp.pictures) and their ParaView files (shellbvp.paraview).

References, each from another route than the module's: what meshio reads back from a
written file against the equilibrium's own arrays (its meridian r, z and its fields); the
reference sphere of the cap in closed form (r0 = sin s, z0 = cos s - 1, normal (sin s,
cos s)); a collection parsed as XML here. Shells of other kinds (two ends, kinks, two
poles) are drawn and written in their undeformed state, built here from the geometry
(an exact equilibrium at zero load, no solve): the pictures' and files' handling of
pieces, joints and poles without compiling a solver per scene. The lobed state's field
against the 2D discretisation's own synthesis is in test_fourier2d.py (it shares that
file's discretisation).
"""

import math
import xml.etree.ElementTree as ET

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

import meshio  # noqa: E402

import shellbvp  # noqa: E402
from shellbvp import geometry as g  # noqa: E402
from shellbvp.fields import reference_point  # noqa: E402
from shellbvp.paraview import write_surface  # noqa: E402
from shellbvp.surface import (EQUILIBRIUM_FIELDS, OutputUnits, equilibrium_surface,  # noqa: E402
                              ring)
from shellbvp.problems import cap_eversion as ce  # noqa: E402

THETA, H = math.pi / 6, 0.01


@pytest.fixture(scope="module")
def branch():
    """The default cap to past its snap (the branch of test_plotting.py: its programs are
    shared within a test process)."""
    return ce.branch(THETA, H, kappa_max=4.5)


@pytest.fixture(scope="module")
def snap(branch):
    return branch.folds[0].equilibrium


def undeformed(scene, nodes=17):
    """The shell of ``scene`` in its stress-free reference state as an Equilibrium: per
    piece Chebyshev-Lobatto nodes (an interface once, a pole's end at an offset 1e-4),
    the meridian, tangent angle and curvatures of the reference, unit stretches, no
    strain, moment or force."""
    ends = scene.piece_ends
    s, piece = [], []
    for i in range(scene.pieces):
        a, b = ends[i], ends[i + 1]
        t = (1 - np.cos(np.pi * np.arange(nodes) / (nodes - 1))) / 2
        x = a + (b - a) * t
        if i == 0 and scene.geometry.poles[0]:
            x[0] = 1e-4
        if i == scene.pieces - 1 and scene.geometry.poles[1]:
            x[-1] = b - 1e-4
        keep = slice(None) if i == 0 else slice(1, None)
        s.append(x[keep])
        piece.append(np.full(x[keep].size, i))
    s, piece = np.concatenate(s), np.concatenate(piece)
    r, z, th, k1, k2 = (np.empty(s.size) for _ in range(5))
    for i in range(scene.pieces):
        on = piece == i
        x = reference_point(scene, i, s[on])
        r[on], z[on], th[on], k1[on], k2[on] = (np.broadcast_to(v, s[on].shape)
                                                for v in (x.r, x.z, x.theta, x.k1, x.k2))
    one, zero = np.ones(s.size), np.zeros(s.size)
    return shellbvp.Equilibrium(
        scene=scene, p=0.0, s=s, r=r, z=z, theta=th, lam1=one, lam2=one, k1=k1, k2=k2,
        eps11=zero, eps22=zero, M=zero, F_r=zero, F_z=zero, energy=0.0,
        stretching_energy=0.0, bending_energy=0.0, w=0.0, error_estimate=0.0, stats={},
        success=True, message="undeformed", N1=zero, N2=zero)


def koiter_scene(geometry, ends):
    return shellbvp.Scene(geometry=geometry, h=0.02, material="koiter", nu=0.3, ends=ends)


#: shells of the kinds a meridian has: two ends (a cone frustum: a disc spring), kinks (a
#: cone on a cylinder, two pieces), two poles (a closed sphere)
KINDS = {
    "two ends": lambda: koiter_scene(g.Meridian(g.Cone((0.5, 0.05), (1.0, 0.0))),
                                     ("free", "roller")),
    "kink": lambda: koiter_scene(g.Meridian((g.Cone((0.5, 0.3), (1.0, 0.0)),
                                             g.Cylinder(1.0, (0.0, -1.0)))),
                                 ("free", "clamped")),
    "two poles": lambda: koiter_scene(g.closed_sphere(1.0), ("pole", "pole")),
}


def read(path):
    mesh = meshio.read(path)
    return mesh, mesh.point_data


# --- the surface read back from its file -------------------------------------------------
def test_written_surface_is_the_meridian_turned_and_carries_its_fields(snap, tmp_path):
    eq = snap
    path = tmp_path / "snap.vtu"
    eq.to_vtk(path)
    mesh, data = read(path)
    nw = 64
    ns = eq.s.size
    X = mesh.points.reshape(ns, nw, 3)
    radius = np.hypot(X[..., 0], X[..., 1])
    assert np.allclose(radius, eq.r[:, None], rtol=0, atol=1e-14)
    assert np.allclose(X[..., 2], eq.z[:, None], rtol=0, atol=1e-14)
    angle = np.unwrap(np.arctan2(X[..., 1], X[..., 0]), axis=1)
    assert np.allclose(np.diff(angle, axis=1), 2 * np.pi / nw, atol=1e-9)
    # every field as the equilibrium has it (single precision in the file)
    for name, ref in (("eps11", eq.eps11), ("eps22", eq.eps22), ("k1", eq.k1),
                      ("k2", eq.k2), ("N1", eq.N1), ("N2", eq.N2), ("moment", eq.M / eq.r),
                      ("s", eq.s)):
        v = data[name].reshape(ns, nw)
        assert np.allclose(v, ref[:, None], rtol=1e-6, atol=1e-7 * np.abs(ref).max()), name
    assert np.allclose(data["thickness"], H, rtol=1e-7)
    assert np.allclose(data["kb1"], eq.p - 1, rtol=1e-6)     # the cap: kb = kappa - 1/R0
    # the displacement from the reference sphere, in closed form
    r0, z0 = np.sin(eq.s), np.cos(eq.s) - 1
    u = data["displacement"].reshape(ns, nw, 3)
    assert np.allclose(np.hypot(u[..., 0], u[..., 1]), np.abs(eq.r - r0)[:, None],
                       atol=1e-8)
    assert np.allclose(u[..., 2], (eq.z - z0)[:, None], atol=1e-8)
    un = (eq.r - r0) * np.sin(eq.s) + (eq.z - z0) * np.cos(eq.s)
    assert np.allclose(data["normal_displacement"].reshape(ns, nw), un[:, None], atol=1e-8)
    assert np.abs(un).max() > 0.02                       # the cap at its snap, not at rest
    # quads in (s, omega), the ring closed: every point in 4 cells but the two end rings'
    quads = mesh.cells_dict["quad"]
    assert quads.shape == ((ns - 1) * nw, 4)
    counts = np.bincount(quads.ravel(), minlength=ns * nw).reshape(ns, nw)
    assert (counts[1:-1] == 4).all() and (counts[[0, -1]] == 2).all()
    assert np.all(data["kappa"] == eq.p)


def test_files_are_in_the_units_given(snap, tmp_path):
    """Every kind of field carries its own factor (a scene file's units: here lengths x
    1000, line forces x 7, line moments x 3, the parameter x 2)."""
    eq = snap
    u = OutputUnits(length=1000.0, line_force=7.0, line_moment=3.0, parameter_scale=2.0,
                    parameter="q", length_label="mm")
    write_surface(equilibrium_surface(eq, omega=8, units=u), tmp_path / "mm.vtu")
    mesh, data = read(tmp_path / "mm.vtu")
    X = mesh.points.reshape(eq.s.size, 8, 3)
    assert np.allclose(np.hypot(X[..., 0], X[..., 1]), 1000 * eq.r[:, None], rtol=1e-13)
    for name, ref in (("N2", 7 * eq.N2), ("moment", 3 * eq.M / eq.r), ("eps22", eq.eps22),
                      ("k2", eq.k2 / 1000), ("thickness", 1000 * H + 0 * eq.s),
                      ("s", 1000 * eq.s)):
        assert np.allclose(data[name].reshape(-1, 8), ref[:, None], rtol=1e-6,
                           atol=1e-7 * np.abs(ref).max()), name
    assert np.all(data["q"] == 2 * eq.p)


def test_branch_collection_opens_as_a_series(branch, tmp_path):
    """The .pvd lists one readable file per point, at the parameter's values (this
    branch ends at its fold: the parameter rises all along)."""
    folder = tmp_path / "series"
    pvd = branch.to_vtk(folder)
    sets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
    assert len(sets) == len(branch.points) >= 5
    assert [float(d.get("timestep")) for d in sets] == list(branch.p)
    for d, pt in zip(sets, branch.points):
        mesh = meshio.read(folder / d.get("file"))
        assert np.all(mesh.point_data["kappa"] == pt.p)
    assert sorted(f.name for f in folder.iterdir()) == sorted(
        [d.get("file") for d in sets] + ["branch.pvd"])             # nothing else
    by_index = branch.to_vtk(tmp_path / "i", time="index", name="cap")
    times = [float(d.get("timestep")) for d in ET.parse(by_index).getroot().iter("DataSet")]
    assert times == list(range(len(sets)))


def test_a_collection_through_a_fold_is_timed_by_the_index():
    """ParaView orders a collection by its times: where the parameter turns back (a fold)
    its values would interleave the two sides, so the times are the points' indices."""
    from shellbvp.paraview import collection_times

    assert collection_times([0.0, 1.0, 2.0])[1] == "parameter"
    assert collection_times([3.0, 2.0, 1.0])[1] == "parameter"
    times, kind = collection_times([0.0, 1.0, 0.5])
    assert kind == "index" and list(times) == [0.0, 1.0, 2.0]
    assert collection_times([0.0, 1.0, 1.0])[1] == "index"          # a repeated time too
    assert list(collection_times([0.0, 1.0, 0.5], "parameter")[0]) == [0.0, 1.0, 0.5]
    with pytest.raises(ValueError, match="time must be one of auto, parameter, index"):
        collection_times([0.0], "arclength")


# --- pictures --------------------------------------------------------------------------------
@pytest.mark.parametrize("field", ["normal_displacement", "N2", "moment", "eps11"])
def test_picture_of_a_cap_colours_its_faces_by_the_field(snap, field):
    import matplotlib.pyplot as plt

    ax = snap.plot3d(field, cut=60)
    surface = ax.collections[0]
    colours = surface.get_facecolor()
    cbar = ax.figure.axes[-1]
    assert EQUILIBRIUM_FIELDS[field][0] in cbar.get_ylabel()
    assert len(np.unique(colours.round(6), axis=0)) > 5        # coloured, not uniform
    lo, hi = cbar.get_ylim()
    values = {"normal_displacement": None, "N2": snap.N2, "moment": snap.M / snap.r,
              "eps11": snap.eps11}[field]
    if values is not None:       # the colour range spans the field (symmetric: diverging)
        tol = 1e-12 * np.abs(values).max()
        assert hi >= values.max() - tol and lo <= values.min() + tol
    plt.close("all")


@pytest.mark.parametrize("kind", KINDS)
def test_pictures_and_files_of_every_kind_of_shell(kind, tmp_path):
    """Two ends, kinks, two poles: drawn and written; the file's rings lie on the
    reference meridian (the undeformed state: displacement and strains zero)."""
    import matplotlib.pyplot as plt

    eq = undeformed(KINDS[kind]())
    for field in ("normal_displacement", "kb2", "thickness"):
        eq.plot3d(field, cut=0 if field == "kb2" else 90, axes=field == "thickness")
    plt.close("all")
    eq.to_vtk(tmp_path / "s.vtu", omega=12)
    mesh, data = read(tmp_path / "s.vtu")
    X = mesh.points.reshape(eq.s.size, 12, 3)
    assert np.allclose(np.hypot(X[..., 0], X[..., 1]), eq.r[:, None], atol=1e-14)
    assert np.allclose(X[..., 2], eq.z[:, None], atol=1e-14)
    assert np.abs(data["displacement"]).max() == 0 and np.abs(data["eps22"]).max() == 0
    assert np.allclose(data["kb2"].reshape(-1, 12), eq.k2[:, None], rtol=1e-6, atol=1e-6)


# --- animations ------------------------------------------------------------------------------
def test_animation_of_a_branch_is_a_gif_of_its_frames(branch, tmp_path):
    from PIL import Image

    path = tmp_path / "snap.gif"
    seen = []
    branch.animate(path, frames=3, dpi=30, progress=lambda done, total: seen.append(done))
    with Image.open(path) as im:
        assert im.n_frames == 3
    assert seen == [1, 2, 3]
    assert [f.name for f in tmp_path.iterdir()] == ["snap.gif"]


# --- bad input: a clear error, nothing half-written --------------------------------------
def test_an_unknown_field_names_the_allowed_ones(snap, branch, tmp_path):
    for call in (lambda: snap.plot3d("stress"),
                 lambda: branch.animate(tmp_path / "a.gif", field="stress"),
                 lambda: equilibrium_surface(snap, omega=4).scalar("stress")):
        with pytest.raises(ValueError, match=r"field must be one of normal_displacement, "
                                             r".*N1, N2, moment.*got 'stress'"):
            call()
    assert not list(tmp_path.iterdir())


def test_mp4_without_ffmpeg_says_to_write_a_gif(branch, tmp_path, monkeypatch):
    monkeypatch.setitem(matplotlib.rcParams, "animation.ffmpeg_path",
                        str(tmp_path / "no-ffmpeg-here"))
    with pytest.raises(RuntimeError, match=r"needs ffmpeg.*write a GIF instead \(snap\.gif\)"):
        branch.animate(tmp_path / "snap.mp4")
    with pytest.raises(ValueError, match=r"path must end in one of \.gif, \.mp4"):
        branch.animate(tmp_path / "snap.avi")
    assert not list(tmp_path.iterdir())


def test_unwritable_paths_leave_nothing_behind(snap, branch, tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    with pytest.raises(OSError, match="cannot write .*a-file"):
        snap.to_vtk(blocker / "snap.vtu")
    with pytest.raises(OSError, match="cannot write"):
        branch.to_vtk(blocker / "series")
    with pytest.raises(OSError):
        branch.animate(blocker / "snap.gif", frames=2, dpi=20)
    with pytest.raises(ValueError, match=r"path must end in one of \.vtu, \.vtk"):
        snap.to_vtk(tmp_path / "snap.xyz")
    assert [f.name for f in tmp_path.iterdir()] == ["a-file"]


def test_an_interrupted_series_or_animation_leaves_nothing_behind(branch, tmp_path):
    """An error (here an interrupt from the progress callback) after some files were
    written removes them, the folder this call made, and any temporary file."""
    def stop_at(k):
        def progress(done, total):
            if done == k:
                raise KeyboardInterrupt
        return progress

    with pytest.raises(KeyboardInterrupt):
        branch.to_vtk(tmp_path / "series", progress=stop_at(4))
    with pytest.raises(KeyboardInterrupt):
        branch.animate(tmp_path / "snap.gif", frames=3, dpi=20, progress=stop_at(2))
    assert not list(tmp_path.iterdir())


def test_bad_arguments_are_refused_before_any_work(snap, tmp_path):
    for call, text in ((lambda: snap.plot3d(cut=360), "cut must be an angle in"),
                       (lambda: snap.plot3d(view=(1, 2, 3)), "view must be"),
                       (lambda: snap.plot3d(magnify=0), "magnify must be a positive"),
                       (lambda: snap.plot3d(vmin=1, vmax=0), "vmin must lie below vmax"),
                       (lambda: snap.to_vtk(tmp_path / "a.vtu", omega=2), "omega must be"),
                       (lambda: ring(np.array([np.nan, 1.0])), "omega must be")):
        with pytest.raises(ValueError, match=text):
            call()
    assert not list(tmp_path.iterdir())


# --- the docs page's pictures ----------------------------------------------------------------
ROOT = __import__("pathlib").Path(__file__).resolve().parents[1]
PAGE = ROOT / "docs" / "pictures.md"


def _pictures():
    import re

    return re.findall(r"\]\(figures/(pictures_\w+)\.(png|gif)\)", PAGE.read_text())


def test_the_pages_pictures_exist_and_name_their_scripts():
    """Every picture of the Pictures page is a file under figures/ with the script of its
    name beside it, which the page names."""
    found = _pictures()
    assert {stem for stem, _ in found} >= {"pictures_everting_cap", "pictures_fig3_lobes",
                                          "pictures_bud", "pictures_disc_spring"}
    text = PAGE.read_text()
    for stem, suffix in found:
        assert (ROOT / "figures" / f"{stem}.{suffix}").stat().st_size > 1000, stem
        assert (ROOT / "figures" / f"{stem}.py").is_file(), stem
        assert f"`figures/{stem}.py`" in text, stem


@pytest.mark.slow       # each script compiles its scenes: minutes
@pytest.mark.parametrize("stem", ["pictures_everting_cap", "pictures_disc_spring",
                                  "pictures_fig3_lobes", "pictures_bud"])
def test_the_picture_scripts_regenerate_their_pictures(stem, tmp_path):
    import subprocess
    import sys

    out = subprocess.run([sys.executable, str(ROOT / "figures" / f"{stem}.py"), "--quick",
                          "--out", str(tmp_path)], capture_output=True, text=True,
                         env={**__import__("os").environ, "MPLBACKEND": "Agg"})
    assert out.returncode == 0, out.stderr[-2000:]
    wanted = {f"{s}.{x}" for s, x in _pictures() if s == stem} | {f"{stem}.csv"}
    assert wanted <= {f.name for f in tmp_path.iterdir()}
