"""Scene files (shellbvp.scenefile) and their command line: every example loads, every bad file
is one line naming its key, the units convert (the same shell in metres and in millimetres),
the everting cap's file snaps where the cap module does, the CLI's JSON, and the compiled
programs of a file kept on disk for the next process."""

import json
import math
import re
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import shellbvp
from docs_blocks import ROOT, blocks
from shellbvp.scenefile import SceneFile, example, examples, load_scene

PAGE = ROOT / "docs" / "scene-files.md"
EXAMPLES = ("clamped-plate", "cylinder-growing-ring", "disc-spring", "disc-spring-swelling",
            "everting-cap", "measured-bowl", "pressurised-cylinder")
#: kappa_s R0 of the default cap (Theta = pi/6, h = 0.01, lam = 1, relaxed), from
#: shellbvp.problems.cap_eversion.snap_curvature (the README states it to these digits)
KAPPA_S = 4.2214291314

PLATE = """
title = "plate"
[geometry]
segments = [ { type = "plate", r = [0.0, 1.0], z = 0.0 } ]
thickness = 0.01
[material]
name = "koiter"
E = 1.0
nu = 0.3
[parameter]
name = "p"
from = 0.0
to = 1.0e-6
[loads]
pressure = "p"
[ends]
first = "pole"
second = "clamped"
[observe]
w_centre = "uz(first)"
"""


def _write(tmp_path, text, name="scene.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _scaled(text, length, modulus):
    """The plate of PLATE with lengths times ``length`` and moduli (and the pressure)
    times ``modulus``."""
    return (text.replace("r = [0.0, 1.0]", f"r = [0.0, {1.0 * length!r}]")
            .replace("thickness = 0.01", f"thickness = {0.01 * length!r}")
            .replace("E = 1.0", f"E = {1.0 * modulus!r}")
            .replace("to = 1.0e-6", f"to = {1.0e-6 * modulus!r}")
            .replace('w_centre = "uz(first)"', f'w_centre = "uz(first)"\n'
                     f'w_half = "uz(s={0.5 * length!r})"\n'
                     f'slope_half = "rotation(s={0.5 * length!r})"'))


# --------------------------------------------------------------------------- loading

@pytest.mark.parametrize("name", EXAMPLES)
def test_every_example_loads(name):
    assert name in examples()
    sf = load_scene(example(name))
    assert isinstance(sf, SceneFile) and isinstance(sf.scene, shellbvp.Scene)
    assert sf.scene.geometry.size == pytest.approx(1.0)      # lengths over L inside
    assert sf.observables and sf.title


def test_every_toml_block_of_the_docs_page_loads(tmp_path):
    found = [code for language, code in blocks(PAGE) if language == "toml"]
    assert len(found) >= 7
    kinds, ends = set(), set()
    for k, code in enumerate(found):
        sf = load_scene(_write(tmp_path, code, f"block{k}.toml"))
        kinds |= {type(seg).__name__ for seg in sf.scene.geometry.segments}
        ends |= {e.kind for e in sf.scene.ends}
    assert kinds == {"Plate", "Cylinder", "Cone", "Sphere", "Torus", "Ellipse", "Points"}
    assert ends == {"pole", "free", "clamped", "hinged", "roller", "symmetry"}


def test_load_scene_is_exported():
    assert shellbvp.load_scene is load_scene and shellbvp.SceneFile is SceneFile


def test_units_conversions_of_a_file(tmp_path):
    sf = load_scene(_write(tmp_path, _scaled(PLATE, 1000.0, 1e-6)))
    u = sf.units
    mu = 1e-6 / (2 * 1.3)
    assert u.length == 1000.0 and u.modulus == pytest.approx(mu, rel=1e-15)
    assert u.thickness == pytest.approx(10.0) and sf.scene.h == pytest.approx(0.01)
    # P = p L / (mu h) at the end of the range, t = 1
    assert float(sf.scene.pressure(1.0)) == pytest.approx(1e-12 * 1000.0 / (mu * 10.0))
    assert sf.parameter_value(0.5) == pytest.approx(0.5e-12)
    assert sf.tol == pytest.approx(1e-9 * 1e-12)


def test_expressions_see_the_files_units_and_convert_back(tmp_path):
    text = PLATE.replace('[loads]', '[stimulus]\nkb1 = "k1_ref + p*r"\nkb2 = "0.5*s"\n'
                         'rhob2 = "z + 2"\n[loads]')
    text = text.replace("r = [0.0, 1.0], z = 0.0", "r = [0.0, 4.0], z = 1.0") \
        .replace("thickness = 0.01", 'thickness = "0.04*(1 - r**2/32)"')
    sf = load_scene(_write(tmp_path, text))
    L = 4.0
    s = np.array([0.1, 0.5, 0.9])              # inside: s / L
    g1, g2, kb1, kb2 = sf.scene.field_values(0, s, 0.5)
    r_user = s * L                             # the plate from the axis outward
    assert np.allclose(g1, 1.0) and np.allclose(g2, 1.0)
    assert np.allclose(kb1, (0.0 + 0.5e-6 * r_user) * L)
    assert np.allclose(kb2, 0.5 * s * L * L)
    from shellbvp.fields import reference_point

    x = reference_point(sf.scene, 0, s)
    rhob = sf.scene.through_thickness(x, 0.5)
    assert np.allclose(rhob[1], (1.0 + 2.0) * L)               # rhob2 in 1/length
    assert sf.units.thickness == pytest.approx(0.04)           # the largest, at r = 0
    assert np.allclose(sf.scene.thickness(x), 1 - r_user**2 / 32)


def test_a_new_range_keeps_the_compiled_programs(tmp_path):
    """The parameter's scale is the power of ten nearest |to - from|: editing the range
    within it changes no function's cache key (nothing compiles anew); the scale follows
    the sign of to - from."""
    a = load_scene(_write(tmp_path, PLATE, "a.toml"))
    b = load_scene(_write(tmp_path, PLATE.replace("to = 1.0e-6", "to = 2.0e-6"), "b.toml"))
    c = load_scene(_write(tmp_path, PLATE.replace("from = 0.0", "from = 3.0e-6"), "c.toml"))
    assert a.scale == b.scale == 1e-6 and c.scale == -1e-6
    assert a.scene.pressure.cache_key == b.scene.pressure.cache_key
    assert c.t_range == pytest.approx((-3.0, -1.0))


def test_functions_carry_a_disk_key(tmp_path):
    """The compiled programs of a file are kept on disk: every function the engine keys
    them by has a cache_key, equal for the same file read twice."""
    from shellbvp.kernels import disk_key, kernel_key

    path = _write(tmp_path, PLATE)
    a, b = load_scene(path), load_scene(path)
    for sf in (a, b):
        sc = sf.scene
        functions = (sc.fields, sc.through_thickness, sc.thickness, sc.pressure,
                     *[getattr(e, n) for e in sc.ends for n in ("axial", "radial", "moment")])
        assert disk_key(functions, "parts") is not None
        assert isinstance(sc.pressure.cache_key, str)
    assert kernel_key(a.scene, (False, False)) == kernel_key(b.scene, (False, False))
    assert a.scene.pressure == b.scene.pressure
    assert "1000.0" not in a.scene.pressure.cache_key
    c = load_scene(_write(tmp_path, _scaled(PLATE, 1000.0, 1e-6), "mm.toml"))
    assert c.scene.pressure.cache_key != a.scene.pressure.cache_key   # other numbers


# --------------------------------------------------------------------------- refusals

BAD = [
    # (replace this, with this, the message starts with)
    ('[loads]', '[loadz]', "loadz: unknown key; allowed: title, units, geometry"),
    ('E = 1.0', 'E = -1', "material.E: must be > 0, got -1"),
    ('E = 1.0', 'E = "one"', "material.E: expected a finite number, got a string"),
    ('E = 1.0\n', '', "material.E: missing (required)"),
    ('name = "koiter"', 'name = "rubber"', "material.name: must be one of koiter, cg, nh"),
    ('nu = 0.3', 'nu = 0.3\nlam = 2.0', "material.lam: unknown key; allowed: name, E, nu"),
    ('type = "plate"', 'type = "plane"',
     "geometry.segments[0].type: unknown segment type 'plane'; allowed: plate, cylinder"),
    ('z = 0.0 }', 'z = 0.0, radius = 1 }',
     "geometry.segments[0].radius: unknown key; allowed: type, r, z"),
    ('r = [0.0, 1.0]', 'r = [0.0]', "geometry.segments[0].r: expected a list of 2 numbers"),
    ('{ type = "plate", r = [0.0, 1.0], z = 0.0 }',
     '{ type = "plate", r = [0.0, 1.0], z = 0.0 }, '
     '{ type = "cylinder", radius = -1, z = [0.0, 1.0] }',
     "geometry.segments[1].radius: must be > 0, got -1"),
    ('{ type = "plate", r = [0.0, 1.0], z = 0.0 }',
     '{ type = "plate", r = [0.0, 1.0], z = 0.0 }, '
     '{ type = "cylinder", radius = 1.0, z = [0.5, 1.0] }',
     "geometry.segments: Meridian: segment 1 (Cylinder) does not meet segment 0 (Plate)"),
    ('{ type = "plate", r = [0.0, 1.0], z = 0.0 }',
     '{ type = "sphere", radius = 1.0, angle = [0.0, 4.0] }',
     "geometry.segments[0]: Sphere.angle = (a0, a1) must have a0 != a1 in [0, pi]"),
    ('thickness = 0.01', 'thickness = "0.01*(1 - r)"',
     "geometry.thickness: must be > 0 along the meridian, got 0 at s = 1"),
    ('thickness = 0.01', 'thickness = "0.01*os(r)"',
     "geometry.thickness: unknown function 'os' at column 6"),
    ('thickness = 0.01', 'thickness = 2.0',
     "geometry.thickness: 2 must lie in (1e-06, 1)"),
    ('thickness = 0.01', 'thickness = "__import__(\'os\')"',
     "geometry.thickness: unknown function '__import__' at column 1"),
    ('pressure = "p"', 'pressure = "p*s"', "loads.pressure: unknown name 's' at column 3"),
    ('pressure = "p"', 'pressure = "p.real"', "loads.pressure: attribute access 'p.real'"),
    ('pressure = "p"', 'pressure = "1/p"', "loads.pressure: not finite at p = 0"),
    ('[loads]', '[stimulus]\nkb1 = "k1_ref + exec(p)"\n[loads]',
     "stimulus.kb1: unknown function 'exec' at column 10"),
    ('[loads]', '[stimulus]\ng1 = "1 - 2*r"\n[loads]',
     "stimulus.g1: must be finite and > 0 along the meridian, got "),
    ('[loads]', '[stimulus]\nbreaks = [2.0]\n[loads]',
     "stimulus.breaks: 2 outside the meridian's interior (0, 1)"),
    ('first = "pole"', 'first = "free"',
     "ends.first: the meridian's first end is on the axis (r = 0): it must be 'pole'"),
    ('second = "clamped"', 'second = "pole"',
     "ends.second: 'pole' but the meridian's second end is at r = 1"),
    ('second = "clamped"', 'second = "clamp"', "ends.second: must be one of pole, free"),
    ('second = "clamped"', 'second = "clamped"\nsecond_moment = "p"',
     "ends.second_moment: a clamped end takes no moment"),
    ('second = "clamped"', 'second = "symmetry"',
     "ends.second: 'symmetry' needs the tangent parallel to the axis"),
    ('to = 1.0e-6', 'to = 0.0', "parameter.to: must differ from parameter.from"),
    ('name = "p"', 'name = "s"', "parameter.name: must be a name (letters, digits, _) other"),
    ('to = 1.0e-6', 'to = 1.0e-6\nfolds = 0', "parameter.folds: expected an integer >= 1"),
    ('w_centre = "uz(first)"', 'w_centre = "uz(middle)"',
     "observe.w_centre: cannot read 'uz(middle)' at column 1"),
    ('w_centre = "uz(first)"', 'w_centre = "uz(s=3)"',
     "observe.w_centre: s = 3 outside the meridian, s in [0, 1]"),
    ('w_centre = "uz(first)"', 'energy = "uz(first)"', "observe.energy: the name is taken"),
    ('[ends]', '[solver]\nmethod = "magic"\n[ends]', "solver.method: must be one of spectral"),
    ('[ends]', '[solver]\npoints = 1\n[ends]', "solver.points: expected an integer in [2, 100000]"),
    ('[ends]', '[solver]\nmonitor = "uz(third)"\n[ends]', "solver.monitor: monitor 'uz(third)'"),
    ('[material]', 'x = = 1\n[material]', "not a TOML file: "),
    ('pressure = "p"', 'pressure = "p"\npole = "second"',
     "loads.pole: names the pole of a pole_force or pole_displacement, and there is none"),
    ('pressure = "p"', 'pole_force = "p"\npole = "second"',
     "loads.pole: the second end is not a pole (on the axis); the poles are: first"),
]


@pytest.mark.parametrize("old,new,start", BAD, ids=[b[2].split(":")[0] for b in BAD])
def test_bad_files_are_one_line_naming_the_key(old, new, start, tmp_path):
    assert old in PLATE
    with pytest.raises(ValueError) as e:
        load_scene(_write(tmp_path, PLATE.replace(old, new, 1)))
    message = str(e.value)
    assert "\n" not in message and message.startswith(start), message
    assert e.value.__traceback__ is not None and e.value.__cause__ is None


def test_the_docs_pages_messages_are_the_real_ones(tmp_path):
    """Every line of the page's list of errors is the start of the message of a bad file
    (up to its "...")."""
    cap = PLATE.replace('{ type = "plate", r = [0.0, 1.0], z = 0.0 }',
                        '{ type = "sphere", radius = 1.0, centre_z = -1.0, angle = [0.0, 0.5] }')
    cap = cap.replace('second = "clamped"', 'second = "free"').replace('name = "p"',
                                                                     'name = "kappa"')
    files = [PLATE.replace(old, new) for old, new, _ in BAD] + [
        PLATE.replace('type = "plate"', 'type = "cylindre"'),
        PLATE.replace('r = [0.0, 1.0]', 'r = [0.3, 1.0]'),
        PLATE.replace('to = 1.0e-6', 'to = 1.0e-6\nfold = 1'),
        cap.replace('[loads]\npressure = "p"', '[stimulus]\nkb1 = "k1_ref + kapa"')]
    messages = []
    for k, text in enumerate(files):
        with pytest.raises(ValueError) as e:
            load_scene(_write(tmp_path, text, f"{k}.toml"))
        messages.append(str(e.value))
    listed = [code for language, code in blocks(PAGE) if language == "text"][-1]
    for line in listed.strip().splitlines():
        head = line.split("...")[0].rstrip()
        assert any(m.startswith(head) for m in messages), line


def test_a_missing_file_is_a_value_error(tmp_path):
    with pytest.raises(ValueError, match="cannot read the scene file"):
        load_scene(tmp_path / "nowhere.toml")
    with pytest.raises(ValueError, match="no example scene 'nowhere'; examples: "):
        example("nowhere")


# --------------------------------------------------------------------------- results

@pytest.fixture(scope="module")
def plate_runs(tmp_path_factory):
    """The plate of PLATE followed in metres (N/m^2) and in millimetres (N/mm^2)."""
    folder = tmp_path_factory.mktemp("plates")
    return {unit: load_scene(_write(folder, _scaled(PLATE, k, m), f"{unit}.toml")).follow()
            for unit, k, m in (("m", 1.0, 1.0), ("mm", 1000.0, 1e-6))}


def test_same_shell_in_metres_and_millimetres(plate_runs):
    """Lengths x 1000 and moduli (and the pressure) x 1e-6 (N/m^2 -> N/mm^2): the same
    observables, lengths x 1000, rotations equal, energies x 1e3 (N m -> N mm)."""
    a, b = plate_runs["m"], plate_runs["mm"]
    assert a.columns == b.columns and len(a.rows) == len(b.rows) > 5
    A, B = np.array(a.rows, dtype=float), np.array(b.rows, dtype=float)
    values = [0, 2, 4, 6, 8]                       # p, w_centre, w_half, slope, energy
    scale = np.array([1e-6, 1e3, 1e3, 1.0, 1e3])
    for k, c in enumerate(values):
        assert np.allclose(A[:, c] * scale[k], B[:, c], rtol=1e-7,
                           atol=1e-10 * np.abs(B[:, c]).max()), a.columns[c]
        # the error estimates (the next column) are at round-off in either unit: both far
        # below the tolerance the values agree to
        assert np.all(A[:, c + 1] * scale[k] <= 1e-9 * np.abs(B[:, c]).max()), a.columns[c]
        assert np.all(B[:, c + 1] <= 1e-9 * np.abs(B[:, c]).max()), b.columns[c]
    assert a.last["w_centre"] < 0 and a.last["slope_half"] > 0     # sags: the slope turns up
    assert b.last["w_centre"] == pytest.approx(1e3 * a.last["w_centre"], rel=1e-7)


def test_small_pressure_gives_kirchhoffs_plate(plate_runs):
    """An exact reference for the conversions: at a small pressure the clamped plate's
    centre deflects by p a^4 / (64 D), D = E h^3 / (12 (1 - nu^2)), in the file's units
    (solved on the scene the fixture compiled)."""
    for unit, a, E, h in (("m", 1.0, 1.0, 0.01), ("mm", 1000.0, 1e-6, 10.0)):
        sf = plate_runs[unit].scene_file
        p = 1e-4 * sf.stop                       # w ~ 1e-3 h: linear to ~1e-6
        eq = shellbvp.solve(sf.scene, p / sf.scale, estimate_error=False)
        w = eq.w * sf.units.length               # the monitor: uz(first) - uz(second)
        D = E * h**3 / (12 * (1 - 0.3**2))
        assert w == pytest.approx(-p * a**4 / (64 * D), rel=1e-5), unit


def test_table_csv_and_summary(plate_runs, tmp_path):
    run = plate_runs["m"]
    out = tmp_path / "plate.csv"
    run.to_csv(out)
    lines = out.read_text().splitlines()
    assert lines[0] == ("p,p_error,w_centre[length],w_centre_error[length],w_half[length],"
                        "w_half_error[length],slope_half[rad],slope_half_error[rad],"
                        "energy[modulus*length^3],energy_error[modulus*length^3],is_fold,"
                        "is_requested")
    assert len(lines) == len(run.rows) + 1 == len(run.branch.points) + 1
    assert [float(v) for v in lines[-1].split(",")[:10]] == list(run.rows[-1][:10])
    summary = json.loads(json.dumps(run.summary()))
    assert summary["folds"] == [] and summary["stop"] == "reached p = 1e-06 (to)"
    assert summary["complete"] and summary["at"] == [] and summary["missing"] == []
    assert set(summary["last"]) == {"p", "p_error", "w_centre", "w_centre_error", "w_half",
                                    "w_half_error", "slope_half", "slope_half_error"}
    assert summary["last"]["p"] == 1e-6           # the last step lands on 'to'
    for name in ("w_centre", "w_half", "slope_half"):
        assert 0 < summary["last"][f"{name}_error"] < 1e-9 * abs(summary["last"][name])


@pytest.mark.slow
def test_everting_cap_file_snaps_where_the_cap_module_does():
    """kappa_s of the everting cap's file against shellbvp.problems.cap_eversion, each
    within the other's error estimate (plus the round-off of the fold)."""
    from shellbvp.problems import cap_eversion as ce

    run = load_scene(example("everting-cap")).follow()
    fold = run.folds[0]
    ref = ce.snap_curvature(math.pi / 6, 0.01, tol=1e-10)
    assert fold["p"] == pytest.approx(ref.kappa_s, abs=fold["p_error"]
                                      + ref.error_estimate + 1e-12)
    assert fold["p"] == pytest.approx(KAPPA_S, abs=1e-10)
    # the edge's displacement relative to the apex, R0 = 1
    assert fold["w_edge"] == pytest.approx(ref.w_s, abs=1e-9)


# --------------------------------------------------------------------------- command line

def _cli(*argv, cwd=None, env=None):
    """Run the command line in a new process, as a user does: JAX's compilation cache on
    (the test process turns it off for itself), so that commands on one file share their
    compiled programs."""
    env = {**os.environ, "SHELLBVP_JAX_CACHE": "on", **(env or {})}
    return subprocess.run([sys.executable, "-m", "shellbvp.cli", *argv], capture_output=True,
                          text=True, cwd=cwd, env=env)


def test_cli_follow_json_csv_and_vtk(tmp_path):
    """One JSON object on stdout (the ParaView files and any progress never in it), the
    CSV, and the ParaView collection of the branch in the file's units (mm, N/mm)."""
    import xml.etree.ElementTree as ET

    import meshio

    out = _cli("follow", "disc-spring", "--json", "--csv", str(tmp_path / "d.csv"),
               "--vtk", str(tmp_path / "vtk"))
    assert out.returncode == 0, out.stderr
    lines = out.stdout.strip().splitlines()
    assert len(lines) == 1
    sets = list(ET.parse(tmp_path / "vtk" / "branch.pvd").getroot().iter("DataSet"))
    table = [r.split(",") for r in (tmp_path / "d.csv").read_text().splitlines()]
    fold_column = table[0].index("is_fold")
    points = [float(r[0]) for r in table[1:] if r[fold_column] == "0"]  # q of every point
    assert [float(d.get("timestep")) for d in sets] == pytest.approx(points, rel=1e-12)
    last = meshio.read(tmp_path / "vtk" / sets[-1].get("file"))
    radius = np.hypot(last.points[:, 0], last.points[:, 1])
    assert radius.min() == pytest.approx(25.0, rel=0.01) and radius.max() == \
        pytest.approx(50.0, rel=0.01)                    # the spring's edges, in mm
    assert np.all(last.point_data["q"] == pytest.approx(points[-1], rel=1e-12))
    result = json.loads(lines[0])
    assert set(result) == {"folds", "at", "last", "stop", "complete", "missing", "error_note"}
    assert result["stop"] == "after 1 fold(s)" and result["complete"]
    fold = result["folds"][0]
    assert set(fold) == {"p", "p_error", "deflection", "deflection_error", "rotation_inner",
                         "rotation_inner_error"}
    # the disc spring of examples/disc-spring.toml snaps through at q = 3.15 N/mm, its
    # inner edge 1.33 mm down, i.e. half way to the plane of its outer edge (2.5 mm)
    assert fold["p"] == pytest.approx(3.1506415, abs=1e-6)
    assert 0 < fold["p_error"] < 1e-8
    assert fold["deflection"] == pytest.approx(-1.329760, abs=1e-5)
    assert 0 < fold["deflection_error"] < 1e-6
    assert result["last"]["p"] < fold["p"]         # the branch turned back after the fold
    header = (tmp_path / "d.csv").read_text().splitlines()[0]
    assert header == ("q[N/mm],q_error[N/mm],deflection[mm],deflection_error[mm],"
                      "rotation_inner[rad],rotation_inner_error[rad],energy[MPa*mm^3],"
                      "energy_error[MPa*mm^3],is_fold,is_requested")


def test_cli_stability_json():
    out = _cli("stability", "disc-spring", "--json")
    assert out.returncode == 0, out.stderr
    result = json.loads(out.stdout)
    assert result["kind"] == "fold" and result["n"] == 0
    assert result["p"] == pytest.approx(3.1506415, abs=1e-6)
    assert result["nearby"] == [] and "note" not in result     # a fold has no cluster


@pytest.mark.slow
def test_cli_stability_of_the_everting_cap_file_is_the_cap_modules():
    """The cap's first instability is a bifurcation into n = 3 waves before the snap
    (``shellbvp stability`` of the built-in cap); the file finds the same within the
    estimates."""
    runs = [json.loads(_cli(*argv).stdout) for argv in
            (("stability", "everting-cap", "--json"), ("stability", "--json"))]
    for r in runs:
        assert r["kind"] == "bifurcation" and r["n"] == 3
        assert r["nearby"][0] == {"n": 3, "p": r["p"], "error_estimate": r["error_estimate"]}
    assert runs[0]["p"] == pytest.approx(runs[1]["p"], abs=runs[0]["error_estimate"]
                                         + runs[1]["error_estimate"])


@pytest.mark.parametrize("argv,text,start", [
    (["follow", "{file}"], PLATE.replace("E = 1.0", "E = -1"),
     "shellbvp: error: {file}: material.E: must be > 0, got -1"),
    (["stability", "{file}", "--json"], PLATE.replace("[observe]", "[observe]\n x = \"y\""),
     "shellbvp: error: {file}: observe.x: cannot read 'y'"),
    (["follow", "missing.toml"], None, "shellbvp: error: missing.toml: cannot read the scene"),
    (["follow", "nothing"], None, "shellbvp: error: nothing: no example scene 'nothing'"),
    (["stability", "{file}", "--theta", "0.3"], PLATE,
     "shellbvp: error: --theta sets the built-in cap"),
])
def test_cli_bad_file_exits_2_with_one_line(argv, text, start, tmp_path, monkeypatch, capsys):
    from shellbvp import cli

    monkeypatch.chdir(tmp_path)
    file = str(_write(tmp_path, text)) if text is not None else ""
    with pytest.raises(SystemExit) as e:
        cli.main([a.format(file=file) for a in argv])
    assert e.value.code == 2
    out = capsys.readouterr()
    err = out.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(start.format(file=file)), out.err
    assert out.out == ""


def test_cli_bad_file_in_a_new_process(tmp_path):
    """The same from ``python -m shellbvp.cli``: exit code 2, one line, no traceback."""
    file = str(_write(tmp_path, PLATE.replace('type = "plate"', 'type = "disk"')))
    out = _cli("follow", file, "--json")
    assert out.returncode == 2 and out.stdout == ""
    assert out.stderr.strip().splitlines() == [
        f"shellbvp: error: {file}: geometry.segments[0].type: unknown segment type 'disk'; "
        f"allowed: plate, cylinder, cone, sphere, torus, ellipse, points"]


def test_cli_solver_failure_exits_1(tmp_path):
    """A plate asked for a curvature of 30 / h at once (no solution near the flat start)
    is a solver failure: exit 1, one line."""
    text = PLATE.replace("[loads]", '[stimulus]\nkb1 = "3000 + p"\nkb2 = "3000 + p"\n[loads]')
    out = _cli("follow", str(_write(tmp_path, text)))
    assert out.returncode == 1
    err = out.stderr.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("shellbvp: solver failure: continuation: no "
                                               "solution at the start"), out.stderr


@pytest.mark.slow
def test_second_process_loads_the_compiled_programs(tmp_path):
    """A scene file's compiled programs are kept on disk: a second run in a new process
    loads them (the first traces and compiles). Timed, not asserted: printed."""
    env = {"SHELLBVP_CACHE_DIR": str(tmp_path / "cache"), "SHELLBVP_JAX_CACHE": "on"}
    times, entries, results = [], [], []
    for _ in range(2):
        t0 = time.perf_counter()
        out = _cli("follow", "clamped-plate", "--json", env=env)
        times.append(time.perf_counter() - t0)
        assert out.returncode == 0, out.stderr
        results.append(json.loads(out.stdout))
        entries.append(sorted(p.name for p in (tmp_path / "cache").rglob("*") if p.is_file()))
    assert entries[0], "nothing kept on disk"
    assert entries[1] == entries[0], "the second process traced or compiled anew"
    assert results[1] == results[0]
    print(f"\nshellbvp follow clamped-plate in fresh processes: first {times[0]:.1f} s, "
          f"second {times[1]:.1f} s ({len(entries[0])} files on disk)")


def test_a_point_force_in_newtons_on_a_plate_in_millimetres(tmp_path):
    """``[loads] pole_force`` on the clamped plate of PLATE in millimetres and N/mm^2: its
    centre deflection is Kirchhoff's w(0) = -F a^2 / (16 pi D) (D = E h^3 / 12 (1 - nu^2))
    to 1e-5 (the geometric nonlinearity at this load, O((w/h)^2) ~ 1e-6). A pole_force on
    a meridian without a pole is named."""
    a, h, E, nu, F = 250.0, 2.5, 210000.0, 0.3, 1.0
    text = (PLATE.replace("r = [0.0, 1.0]", f"r = [0.0, {a}]")
            .replace("thickness = 0.01", f"thickness = {h}").replace("E = 1.0", f"E = {E}")
            .replace('name = "p"', 'name = "F"').replace("to = 1.0e-6", f"to = {F}")
            .replace('pressure = "p"', 'pole_force = "-F"'))
    sf = shellbvp.load_scene(_write(tmp_path, text))
    last = sf.follow().last
    D = E * h**3 / (12 * (1 - nu**2))
    assert abs(last["w_centre"] / (-last["p"] * a**2 / (16 * math.pi * D)) - 1) < 1e-5
    annulus = text.replace("r = [0.0, 250.0]", "r = [50.0, 250.0]").replace(
        'first = "pole"', 'first = "free"')
    with pytest.raises(ValueError, match="loads.pole_force: the meridian has no pole"):
        shellbvp.load_scene(_write(tmp_path, annulus, "annulus.toml"))


def test_solver_points_draws_a_finer_branch(tmp_path):
    """``[solver] points = 40``: the plate's monotone branch gets at least 40 points (it has
    a handful without: the step control takes long steps where the branch is straight), and
    still runs to ``to``."""
    plain = load_scene(_write(tmp_path, PLATE)).follow()
    fine = load_scene(_write(tmp_path, PLATE.replace("[ends]", "[solver]\npoints = 40\n[ends]"),
                             "fine.toml")).follow()
    assert len(plain.rows) < 40 <= len(fine.rows)
    assert fine.last["p"] >= 1.0e-6 and "to" in fine.stop      # it still runs to `to`


def test_a_clamped_edges_reaction_under_pressure(tmp_path):
    """``force(second)`` of a clamped edge under a pressure is the pressure times the area
    the edge encloses, p pi a^2 (the axial equilibrium of the whole shell, exact: the
    pressure on a surface closed by a flat disc has zero resultant), on the plate and on a
    spherical cap (a = sin 0.5), to round-off. It is the force resultant F_z + p r^2 / 2,
    not the multiplier F_z alone (zero here)."""
    cap = PLATE.replace('{ type = "plate", r = [0.0, 1.0], z = 0.0 }',
                        '{ type = "sphere", radius = 1.0, centre_z = -1.0, angle = [0.0, 0.5] }')
    for text, a in ((PLATE, 1.0), (cap, math.sin(0.5))):
        text = text.replace('w_centre = "uz(first)"', 'reaction = "force(second)"')
        last = load_scene(_write(tmp_path, text)).follow().last
        assert last["reaction"] == pytest.approx(math.pi * last["p"] * a**2, rel=1e-10)


ANNULUS_BAND = """
[geometry]
segments = [ { type = "plate", r = [1.0, 2.0] } ]
thickness = 0.01
[material]
name = "koiter"
E = 1.0
nu = 0.3
[parameter]
name = "g"
from = 0.0
to = 1.0e-6
[stimulus]
g1 = "1 + where(s OP 0.5, g, 0)"
g2 = "1 + where(s OP 0.5, g, 0)"
breaks = [0.5]
[ends]
first = "free"
second = "roller"
"""


@pytest.mark.parametrize("op", ["<", "<="])
def test_a_step_at_a_break_takes_each_pieces_side(op, tmp_path):
    """A flat annulus (r from 1 to 2) whose inner band r < 1.5 grows in-plane by g, the step
    written in s at its break either way: each piece sees its own side, so the inner edge
    moves as plane-stress elasticity with that eigenstrain says (Lame: u(a) = a g (b^2 -
    a^2) / (c^2 - a^2), a, b, c = 1, 1.5, 2) to 1e-5 (measured 1.3e-6, as with fields
    written per piece in Python); before, the node at the break took the other side's value
    for one of the two and the edge was off by 1.5e-4 with an error estimate of 7e-11."""
    g = 1e-6
    sf = load_scene(_write(tmp_path, ANNULUS_BAND.replace("OP", op)))
    eq = shellbvp.solve(sf.scene, g / sf.scale)
    u = (eq.r[0] - 0.5) * 2.0                      # r inside is r / L, L = 2
    assert abs(u / (g * (1.5**2 - 1) / (2**2 - 1)) - 1) < 1e-5


def test_a_ring_load_in_newtons_on_a_plate_in_millimetres(tmp_path):
    """``[loads] rings``: the clamped plate of PLATE in millimetres, a total force F (N) down
    on the circle r = b = 100 mm: Kirchhoff's centre deflection
    -F / (8 pi D) [(a^2 - b^2) / 2 + b^2 ln(b / a)] (Timoshenko & Woinowsky-Krieger, Sec. 19)
    to 1e-5. A ring outside the meridian, one without a load and a misspelt key are named."""
    a, b, h, E, nu, F = 250.0, 100.0, 2.5, 210000.0, 0.3, 1.0
    text = (PLATE.replace("r = [0.0, 1.0]", f"r = [0.0, {a}]")
            .replace("thickness = 0.01", f"thickness = {h}").replace("E = 1.0", f"E = {E}")
            .replace('name = "p"', 'name = "F"').replace("to = 1.0e-6", f"to = {F}")
            .replace('pressure = "p"', f'rings = [{{ s = {b}, axial = "-F" }}]'))
    sf = shellbvp.load_scene(_write(tmp_path, text))
    assert sf.scene.rings[0].s == pytest.approx(b / a)
    last = sf.follow().last
    D = E * h**3 / (12 * (1 - nu**2))
    expected = -last["p"] / (8 * math.pi * D) * ((a**2 - b**2) / 2 + b**2 * math.log(b / a))
    assert abs(last["w_centre"] / expected - 1) < 1e-5
    for bad, message in ((f"s = {2 * a}", "loads.rings[0].s: must lie inside the meridian"),
                         (f's = {b}, radial = "0", spin = "1"', "loads.rings[0].spin: unknown"),
                         ):
        with pytest.raises(ValueError, match=re.escape(message)):
            shellbvp.load_scene(_write(tmp_path, text.replace(f"s = {b}", bad), "bad.toml"))
    with pytest.raises(ValueError, match=re.escape("loads.rings[0]: give axial, radial")):
        shellbvp.load_scene(_write(tmp_path, text.replace(', axial = "-F"', ""), "bad.toml"))
    two = text.replace(f'rings = [{{ s = {b}, axial = "-F" }}]',
                       f'rings = [{{ s = {b}, axial = "-F" }}, {{ s = {b}, radial = "F" }}]')
    with pytest.raises(ValueError, match=re.escape("loads.rings: two rings at s = 100;")):
        shellbvp.load_scene(_write(tmp_path, two, "two.toml"))


def test_an_indented_plate_reports_the_indenters_force(tmp_path):
    """``[loads] pole_displacement`` (displacement control) with the observable
    ``force(first)``: the clamped plate of PLATE in millimetres and N/mm^2, its centre
    pushed down by d, takes Kirchhoff's force -16 pi D d / a^2 (N) to 1e-4 (the geometric
    nonlinearity at d / t = 0.006, ~4e-5); a force is read at an end only."""
    a, h, E, nu = 250.0, 2.5, 210000.0, 0.3
    text = (PLATE.replace("r = [0.0, 1.0]", f"r = [0.0, {a}]")
            .replace("thickness = 0.01", f"thickness = {h}").replace("E = 1.0", f"E = {E}")
            .replace('name = "p"', 'name = "d"').replace("to = 1.0e-6", "to = 0.01")
            .replace('pressure = "p"', 'pole_displacement = "-d"')
            .replace('w_centre = "uz(first)"', 'w_centre = "uz(first)"\nF = "force(first)"'))
    last = shellbvp.load_scene(_write(tmp_path, text)).follow().last
    D = E * h**3 / (12 * (1 - nu**2))
    assert last["w_centre"] == pytest.approx(-last["p"], rel=1e-12)
    assert abs(last["F"] / (-16 * math.pi * D * last["p"] / a**2) - 1) < 1e-4
    with pytest.raises(ValueError, match="force\\(...\\) is read at an end"):
        shellbvp.load_scene(_write(tmp_path, text.replace('"force(first)"', '"force(s=1)"'),
                                   "bad.toml"))
