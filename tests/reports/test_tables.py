"""Family files, LaTeX tables of exact critical loss rates, verdicts and a family's queries as columns,
and their compilation."""

import json
import shutil
import subprocess
import sys

import pytest
import sympy as sp

import symkf as sk

from symkf.exact.numbers import sympify as exact
from symkf import GilbertElliott, examples
from symkf.io import files
from symkf.errors import FileFormatError, InputError
from symkf.exact.algebraic import AlgebraicNumber
from symkf.io.families import load_family
from symkf.engine.stability import stability
from symkf.reports.tables import Cell, Table, escape, family_table, verdict_table
from conftest import ROOT

FAMILIES = examples.directory() / "families"

SMALL_ROTATIONS = """
[family]
name = "small_rotations"
description = "$A = 2R(\\\\pi/g)$, $d$ sensors $[1,\\\\ 0]$"
kind = "rotation"
[grid]
period = { from = 1, to = 4 }
sensors = [1, 2, 3]
[constants]
alpha = "2"
"""


def _write(tmp_path, text, name="family.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def rotations(tmp_path_factory):
    return family_table(_write(tmp_path_factory.mktemp("rot"), SMALL_ROTATIONS, "small_rotations.toml"))


@pytest.fixture(scope="module")
def angle_alpha():
    return family_table(FAMILIES / "rotation-angle-alpha.toml")


@pytest.fixture(scope="module")
def ge_recovery():
    return family_table(FAMILIES / "ge-recovery.toml")


@pytest.fixture(scope="module")
def lqg_input_rank():
    return family_table(FAMILIES / "lqg-input-rank.toml")


@pytest.fixture(scope="module")
def bracket():
    """nu_c of A = diag(2, 3, 5) with two inputs B = [[1, 0], [0, 1], [1, 1]] on one channel: no
    closed form; the quotient bound of the whole plant, rank B = 2 and |det A|^2 = 900, is
    1 - 900^(-1/2) = 29/30 (the smaller quotients give 24/25, 14/15, 9/10), certified within 1e-12."""
    from symkf.io.families import systems_family
    S = sk.System(A=[[2, 0, 0], [0, 3, 0], [0, 0, 5]], sensors=[sk.Sensor(C=[[1, 1, 1]])],
                  actuators=[sk.Actuator(B=[[1, 0], [0, 1], [1, 1]])])
    return family_table(systems_family([S], compute="critical_arrival_rate"), progress=False)


@pytest.fixture(scope="module")
def verdicts():
    return verdict_table()


def _exact(table, row, col):
    return exact(table.to_dict()["rows"][row]["cells"][col]["exact"])


# -- values -------------------------------------------------------------------------------------

def test_rotation_family_hand_derived_values(rotations):
    # A = 2 R(pi/g) has governing period g; the g rows C A^k (k < g) of each sensor are pairwise
    # independent, so a maximal rank-deficient set is one phase of all d sensors and
    # 2^(2g) eps^(d (g - 1)) < 1 decides: eps_c = 2^(-2g / (d (g - 1))).
    assert _exact(rotations, 1, 0) == sp.Rational(1, 16)           # 2R(pi/2), C = [1 0]
    assert _exact(rotations, 2, 0) == sp.Rational(1, 8)
    assert _exact(rotations, 2, 1) == sp.sqrt(2) / 4
    assert _exact(rotations, 3, 0) == 2 ** sp.Rational(1, 3) / 8
    for row, g in enumerate((2, 3, 4), start=1):
        for col, d in enumerate((1, 2, 3)):
            assert _exact(rotations, row, col) == sp.Integer(2) ** sp.Rational(-2 * g, d * (g - 1))
            # identical sensors: all d copies must be lost, so eps_c(d)^d = eps_c(1)
            assert sp.simplify(_exact(rotations, row, col) ** d - _exact(rotations, row, 0)) == 0


def test_unobservable_member_is_marked_not_fatal(rotations):
    # period 1: A = 2 R(pi) = -2 I and C = [1, 0] does not see the second coordinate
    row = rotations.to_dict()["rows"][0]
    assert row["label"] == "1"
    assert all("detectability of (A, C) fails" in c["inapplicable"] for c in row["cells"])
    assert "period = 1, sensors = 2" in row["cells"][1]["inapplicable"]
    assert row["cells"][1]["point"] == {"period": "1", "sensors": "2"}
    assert rotations.rows[0][1][0].plain == "---"
    assert "---: the theorem's assumptions fail (" in rotations.to_latex()


def test_template_family_angle_alpha(angle_alpha):
    # eps_c = alpha^(-2g/(g-1)) with g = 2, 3, 5, 6 for theta = pi/2, pi/3, 2pi/5, pi/6
    assert [r.plain for r, _ in angle_alpha.rows] == ["pi/2", "pi/3", "2*pi/5", "pi/6"]
    for row, g in enumerate((2, 3, 5, 6)):
        for col, alpha in enumerate((sp.Rational(3, 2), 2, 3)):
            assert sp.simplify(_exact(angle_alpha, row, col) - exact(alpha) ** sp.Rational(-2 * g, g - 1)) == 0
    assert _exact(angle_alpha, 0, 0) == sp.Rational(16, 81)
    assert _exact(angle_alpha, 2, 0) == 4 * sp.sqrt(6) / 27               # (2/3)^(5/2)
    assert angle_alpha.to_dict()["rows"][2]["cells"][0]["class_periods"] == [5]


def test_stability_family_matches_the_system_file(ge_recovery):
    rows = ge_recovery.to_dict()["rows"]
    system, loss = files.load(examples.directory() / "systems" / "ge-two-sensors.toml")  # recover = 1/2
    v = stability(system, loss)
    assert rows[2]["label"] == "1/2"
    assert rows[2]["cells"][0]["stable"] is v.stable is False
    assert exact(rows[2]["cells"][0]["margin"]["exact"]) == v.margins[0].exact
    # every member against the engine called directly (no template, no file)
    for row in rows:
        q = row["label"]
        direct = stability(system, GilbertElliott(["1/4", "1/4"], [q, q]))
        assert row["cells"][0]["stable"] is direct.stable
        assert exact(row["cells"][0]["margin"]["exact"]) == direct.margins[direct.limiting_block].exact


def test_verdict_table_of_the_examples(verdicts):
    data = verdicts.to_dict()
    by_name = {r["label"]: r["cells"] for r in data["rows"]}
    assert "aperiodic-rotation" not in by_name                               # no [loss]
    # design-rotation: A = 2R(pi/2), loss 1/20: alpha^4 eps = 4/5 per period 2, margin sqrt(4/5)
    assert exact(by_name["design-rotation"][3]["exact"]) == 2 * sp.sqrt(5) / 5
    assert by_name["design-rotation"][1] == "stable" and by_name["design-rotation"][2] == "2"
    assert by_name["rotation-pi12-four-sensors"][2] == "12"
    for path in sorted((examples.directory() / "systems").glob("*.toml")):
        system, loss = files.load(path)
        if loss is not None:
            assert (by_name[path.stem][1] == "stable") is stability(system, loss).stable


# -- rendering ------------------------------------------------------------------------------------

def test_cells_keep_exact_values_and_certified_decimals(angle_alpha):
    cell = angle_alpha.to_dict()["rows"][2]["cells"][1]                      # sqrt(2)/8
    assert cell["exact"] == "sqrt(2)/8" and cell["decimal"] == "0.176777"
    lo, hi = map(sp.Rational, cell["interval"])
    assert lo <= sp.sqrt(2) / 8 <= hi and hi - lo < sp.Rational(1, 10 ** 8)
    assert Cell.number(AlgebraicNumber.from_expr(sp.Rational(1, 16))).plain == "1/16 = 0.0625"
    assert Cell.number(AlgebraicNumber.from_expr(1)).plain == "1"


def test_renderings(rotations):
    latex = rotations.to_latex()
    assert latex.startswith(r"\begin{table}") and latex.rstrip().endswith(r"\end{table}")
    for piece in (r"\toprule", r"\midrule", r"\bottomrule", r"\multicolumn{3}{c}{identical sensors $d$}",
                  r"\label{tab:small-rotations}", "governing period", r"\texttt{small\_rotations}"):
        assert piece in latex
    text = str(rotations)
    assert "governing period g \\ identical sensors d" in text and "1/16 = 0.0625" in text
    assert rotations._repr_latex_().startswith(r"$$\begin{array}{l|ccc}")
    assert json.loads(json.dumps(rotations.to_dict()))["axes"] == ["period", "sensors"]


def _no_radical_table():
    root = AlgebraicNumber.from_expr(sp.CRootOf(sp.Symbol("x") ** 5 - sp.Symbol("x") - 1, 0))
    return Table("A value without radicals; " + escape("specials & % # _ { } ~ ^ \\ escaped."), "plain",
                 Cell.text("name_with & specials % # ~ ^"), (Cell.text("value"),),
                 ((Cell.text("x^5 - x - 1"), (Cell.number(root),)),))


def test_control_threshold_cells_are_exact_where_a_closed_form_applies(lqg_input_rank):
    # eps_c = 1/a^2; nu_c = 1 - 16/(25 a^2) at b = 1 (rank B = 1), 1 - 1/a^2 at b = 0 (B invertible)
    doc = lqg_input_rank.to_dict()
    assert doc["columns"] == ["critical loss rate", "critical arrival rate"] and doc["layout"] == "members as rows"
    assert [(r["label"], [c["exact"] for c in r["cells"]]) for r in doc["rows"]] == [
        ("3/2, 1", ["4/9", "161/225"]), ("3/2, 0", ["4/9", "5/9"]), ("2, 1", ["1/4", "21/25"]),
        ("2, 0", ["1/4", "3/4"]), ("3, 1", ["1/9", "209/225"]), ("3, 0", ["1/9", "8/9"])]
    cell = lqg_input_rank.rows[2][1][1]        # a = 2, b = 1: 21/25, rendered as every exact cell
    number = Cell.number(AlgebraicNumber.from_expr(sp.Rational(21, 25)))
    assert (cell.plain, cell.latex, cell.math) == (number.plain, number.latex, number.math)
    assert cell.plain == "21/25 = 0.84" and cell.data == {"point": {"a": "2", "b": "1"}, "class_periods": [1, 1],
                                                          **number.data}


def test_a_bracket_renders_as_an_interval_with_exact_ends(bracket):
    ((_, (cell,)),) = bracket.rows
    upper = sp.Rational(cell.data["upper"])
    assert sp.Rational(29, 30) < upper <= sp.Rational(29, 30) + sp.Rational(1, 10 ** 12)
    assert cell.data["lower"]["exact"] == "29/30" and cell.data["reached"] is True
    shown = format(sp.Float(upper, 30), "f").rstrip("0")   # upper terminates: shown exactly in decimal
    assert sp.Rational(shown) == upper
    assert cell.plain == f"[29/30, {shown}]"
    assert cell.latex == rf"$[\frac{{29}}{{30}},\, {shown}]$" and cell.math == cell.latex[1:-1]
    assert cell.latex in bracket.to_latex() and bracket.to_dict()["rows"][0]["cells"][0]["upper"] == str(upper)


def test_no_radical_form_uses_the_minimal_polynomial():
    cell = _no_radical_table().rows[0][1][0]
    assert "root of $x^{5} - x - 1$" in cell.latex and cell.data["decimal"] == "1.1673"


def test_every_table_compiles_with_pdflatex(tmp_path, rotations, angle_alpha, ge_recovery, verdicts, lqg_input_rank,
                                           bracket):
    if shutil.which("pdflatex") is None:
        pytest.skip("pdflatex is not installed")
    from symkf import bounds  # noqa: F401 -- registers the published bounds' query
    from symkf.io.families import systems_family
    quarter_turn = sk.System(A=[[0, -2], [2, 0]], sensors=[sk.Sensor(C=[[1, 0]])])
    queries = (family_table(_write(tmp_path, PER_SENSOR), progress=False),   # members as rows
               family_table(systems_family([quarter_turn], compute=["bounds"]), progress=False))   # as columns
    for i, table in enumerate((rotations, angle_alpha, ge_recovery, verdicts, _no_radical_table(), *queries,
                               lqg_input_rank, bracket)):
        tex = tmp_path / f"t{i}.tex"
        tex.write_text("\\documentclass{article}\n\\usepackage{booktabs}\n\\begin{document}\n"
                       + table.to_latex() + "\\end{document}\n")
        run = subprocess.run(["pdflatex", "-interaction=nonstopmode", "-halt-on-error", tex.name],
                             cwd=tmp_path, capture_output=True, text=True, timeout=120)
        assert run.returncode == 0, run.stdout[-2000:]
        assert (tmp_path / f"t{i}.pdf").exists()
        assert "Overfull" not in run.stdout, f"table {i} is wider than the text"


def test_example_script_writes_a_table(tmp_path):
    family = _write(tmp_path, SMALL_ROTATIONS.replace("from = 1, to = 4", "from = 2, to = 3"))
    out = tmp_path / "table.tex"
    run = subprocess.run([sys.executable, str(ROOT / "examples" / "critical_table.py"), str(out),
                          "--family", str(family)], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert f"wrote {out.resolve()}" in run.stdout
    tex = out.read_text()   # the one table symkf table writes
    assert tex == family_table(family, progress=False).to_latex() and r"\frac{\sqrt{2}}{4}" in tex


def test_table_write(tmp_path, rotations):
    assert rotations.write(tmp_path / "t.tex").read_text() == rotations.to_latex()


# -- bad family files -----------------------------------------------------------------------------

GOOD_TEMPLATE = """
[family]
[grid]
a = ["2", "3"]
[system]
A = [["a", "0"], ["0", "a/2"]]
[[sensors]]
C = [["1", "1"]]
"""

BAD = [
    ("[grid]\na = [1]\n", "missing table [family]"),
    ("[family]\nkind = \"spiral\"\n[grid]\na = [1]\n", "[family] kind 'spiral' is not one of"),
    ("[family]\ncompute = \"fastest\"\n[grid]\na = [1]\n", "[family] compute 'fastest'"),
    ("[family]\ncolour = 1\n[grid]\na = [1]\n", "[family] unknown key(s) ['colour']"),
    ("[family]\ndigits = 0\n[grid]\na = [1]\n", "[family] digits must be an integer from 1 to 50"),
    ("[family]\n", "[grid] must be a table with one or two parameters"),
    ("[family]\n[grid]\na = [1]\nb = [1]\nc = [1]\n", "[grid] must be a table with one or two parameters"),
    ("[family]\n[grid]\na = []\n", "[grid] a: expected a non-empty list"),
    ("[family]\n[grid]\na = { from = 3, to = 1 }\n", "[grid] a: a range is"),
    ("[family]\n[grid]\na = [inf]\n", "[grid] a[0]: Infinity is not a finite number"),
    ("[family]\n[grid]\na = [\"1/0\"]\n", "[grid] a[0]: division by zero in '1/0'"),
    ("[family]\n[grid]\na = [\"2 + b\"]\n", "[grid] a[0]: unknown name 'b'"),
    ("[family]\n[grid]\na = [1, 1]\n", "[grid] a: values repeat"),
    ("[family]\n[grid]\npi = [1]\n", "parameter name 'pi' must be an identifier other than"),
    ("[family]\n[grid]\nsensors = [0]\n", "[grid] sensors[0]: the number of sensor copies"),
    ("[family]\n[grid]\na = [1]\n[constants]\na = 2\n", "parameter 'a' is in both [grid] and [constants]"),
    ("[family]\n[grid]\na = [1]\n[[sensors]]\nC = [[\"1\"]]\n", "[system]: missing key 'A'"),
    ("[family]\n[grid]\na = [1]\n[system]\nA = [[\"a\"]]\n", "[[sensors]] must list at least one sensor"),
    ("[family]\n[grid]\nb = [1]\n[system]\nA = [[\"2\"]]\n[[sensors]]\nC = [[\"1\"]]\n",
     "parameter 'b' appears in no entry"),
    ("[family]\ncompute = \"stability\"\n[grid]\na = [1]\n[system]\nA = [[\"a\"]]\n[[sensors]]\nC = [[\"1\"]]\n",
     "[loss]: compute = \"stability\" needs a loss model"),
    ("[family]\nkind = \"rotation\"\n[grid]\nperiod = [2]\n", "needs parameter 'alpha' and exactly one of"),
    ("[family]\nkind = \"rotation\"\n[grid]\nperiod = [2]\n[constants]\nalpha = 2\nangle = \"pi/3\"\n",
     "exactly one of 'angle'"),
    ("[family]\nkind = \"rotation\"\n[grid]\nperiod = [2]\n[constants]\nalpha = 2\n[system]\nA = [[\"1\"]]\n",
     "[system] A: kind = \"rotation\" builds A"),
    ("[family\n", "not valid TOML"),
]


@pytest.mark.parametrize("text, message", BAD, ids=[m for _, m in BAD])
def test_bad_family_files_name_file_key_and_problem(tmp_path, text, message):
    path = _write(tmp_path, text)
    with pytest.raises(FileFormatError) as info:
        load_family(path)
    assert str(info.value).startswith(f"{path}: ") and message in str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("text, pieces", [
    (GOOD_TEMPLATE.replace('"a/2"', '"a/"'), ["A[1][1]: not a well-formed expression"]),
    (GOOD_TEMPLATE.replace('C = [["1", "1"]]', 'C = [["1", "1", "1"]]'), ["sensors[0].C: has 3 columns"]),
    (GOOD_TEMPLATE.replace("[[sensors]]", "[loss]\nkind = \"iid\"\nloss = [\"1/2\", \"1/2\"]\n[[sensors]]"),
     ["[loss] gives 2 value(s) for 1 sensor(s)"]),
    # members are read as system files, so their guards apply: no 370-million-digit numbers
    (GOOD_TEMPLATE.replace('"a/2"', '"a^9^9^9"'), ["A[1][1]: the exponent in '(2)^9^9^9' is 387420489, above the cap 10000"]),
])
def test_bad_members_name_file_grid_point_and_entry(tmp_path, text, pieces):
    path = _write(tmp_path, text)
    with pytest.raises(InputError) as info:
        family_table(path)
    assert str(info.value).startswith(f"{path}: at a = 2: ") and "\n" not in str(info.value)
    assert all(p in str(info.value) for p in pieces)


def test_missing_file():
    with pytest.raises(FileFormatError, match="nowhere.toml: no such file"):
        load_family("nowhere.toml")


def test_template_substitutes_exact_values(tmp_path):
    family = load_family(_write(tmp_path, GOOD_TEMPLATE))
    assert [m.label for m in family.members] == ["a = 2", "a = 3"]
    system, loss = family.members[1].system()
    assert system.A == sp.ImmutableMatrix([[3, 0], [0, sp.Rational(3, 2)]]) and loss is None


def test_sensor_copies_repeat_names_and_losses(tmp_path):
    text = GOOD_TEMPLATE.replace("a = [\"2\", \"3\"]", "a = [\"2\"]\nsensors = [2]").replace(
        "[[sensors]]", "[loss]\nkind = \"iid\"\nloss = [\"1/3\"]\n[[sensors]]\nname = \"s\"")
    system, loss = load_family(_write(tmp_path, text)).members[0].system()
    assert system.sensor_names == ("s_1", "s_2") and loss.loss == (sp.Rational(1, 3),) * 2


PER_SENSOR = """
[family]
name = "per-sensor"
compute = ["critical_loss_rate_per_sensor", "stability_margin"]
[grid]
eps = ["1/25", "1/8"]
sensors = [1, 2]
[system]
A = [["0", "-2"], ["2", "0"]]
[[sensors]]
name = "s"
C = [["1", "1"]]
[loss]
kind = "iid"
loss = ["eps"]
"""


def test_a_compute_list_is_a_column_per_query_and_a_row_per_member(tmp_path):
    """2R(pi/2) with d copies of C = [1, 1] at loss eps: C and C A are independent, so a period of
    two steps blinds the filter when the d copies all lose at one phase: stable iff 16 eps^d < 1
    (per sensor 16 eps_s eps^(d - 1) < 1), margin sqrt(16 eps^d) = 4 eps^(d/2), by hand."""
    table = family_table(_write(tmp_path, PER_SENSOR), progress=False)
    doc = table.to_dict()
    assert doc["columns"] == ["eps_c(s)", "eps_c(s_1)", "eps_c(s_2)", "margin"]
    assert [r["label"] for r in doc["rows"]] == ["1/25, 1", "1/25, 2", "1/8, 1", "1/8, 2"]
    cells = [[None if c is None else c["exact"] for c in r["cells"]] for r in doc["rows"]]  # None: no such sensor
    sixteenth = sp.Rational(1, 16)
    expected = [[sixteenth, None, None, sp.Rational(4, 5)],
                [None, 1, 1, sp.Rational(4, 25)],
                [sixteenth, None, None, sp.sqrt(2)],
                [None, sp.Rational(1, 2), sp.Rational(1, 2), sp.Rational(1, 2)]]
    assert [[None if c is None else exact(c) for c in row] for row in cells] == expected
    assert table.columns[1].latex == r"$\varepsilon_c$ (s\_1)" and "stub" in doc and doc["stub"] == "eps, identical sensors d"
    assert r"\max_i \alpha_i^2\rho_i" in table.to_latex()
