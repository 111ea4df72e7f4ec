"""Heavy and hostile input under hard limits: every case runs in a forked child with a CPU and an
address-space limit (conftest.limited), so a regression that hangs or allocates gigabytes fails
the test instead of taking the machine down.  A case passes when the child ends by itself, with
exit status 0-3 (never 70, never a signal) and no traceback: numbers that once hung, command-line
values symkf cannot serve, and fuzzed entries through the library and the command line."""

from __future__ import annotations

import pytest
from hypothesis import Phase, given, settings
from hypothesis import strategies as st

import symkf as sk
from symkf import cli

from conftest import library, limited, system_file


def assert_clean(code: int, err: str) -> None:
    assert code in (0, 1, 2, 3), (code, err[-500:])
    assert "Traceback" not in err


HANGS = ["exp(2*pi*I/99991)", "sqrt(" * 20 + "2" + ")" * 20, "root(2, 99999)", "cos(pi/1000000007)",
         "root(2, 10**12)", "+".join(f"sqrt({p})" for p in (2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37)),
         "cos(pi*sqrt(2))", "9^9^9"]


@pytest.mark.parametrize("text", HANGS)
def test_numbers_that_once_hung_end_at_once_everywhere(tmp_path, text):
    """In A and as a loss, through the library and the CLI: exit 2 in one line, within the limits."""
    code, err = limited(library, lambda: sk.IID([text]))
    assert code == 2, err
    code, err = limited(library, lambda: sk.System(A=[[text]], sensors=[sk.Sensor(C=[[1]])]))
    assert code == 2, err
    for path in (system_file(tmp_path, text), system_file(tmp_path, "2", loss=text, name="l.toml")):
        code, err = limited(cli.main, ["analyze", str(path)])
        assert code == 2 and err.count("\n") == 1, err


@pytest.mark.parametrize("argv, message", [
    (["critical", "{sys}", "--digits", "1000000000"], "--max-digits"),
    (["critical", "{sys}", "--digits", "100000"], "--max-digits"),
    (["simulate", "{sys}", "--paths", "1000000000", "--horizon", "80"], "--max-memory"),
    (["analyze", "/dev/zero"], "is a device"),
    (["table", "{dir}"], "is a directory"),
    (["verify", "/dev/zero"], "is a device"),
    (["analyze", "{cos}"], "rational multiple of pi"),
])
def test_cli_values_it_cannot_serve_are_exit_2(tmp_path, argv, message):
    """Command-line values that once hung, hit MemoryError or exited 70."""
    paths = {"sys": system_file(tmp_path, "2"), "dir": tmp_path, "cos": system_file(tmp_path, "2", "cos(pi*sqrt(2))", "c.toml")}
    code, err = limited(cli.main, [a.format(**{k: str(v) for k, v in paths.items()}) for a in argv])
    assert code == 2 and err.count("\n") == 1 and message in err, err


ENTRY = st.one_of(
    st.sampled_from(HANGS),
    st.text(alphabet=st.sampled_from(list("0123456789.+-*/^()eEIpisqrtcoxn_,")), max_size=30),
    st.tuples(st.sampled_from(["sqrt", "root", "cos", "exp", "sin"]), st.integers(-10 ** 12, 10 ** 12),
              st.integers(-10 ** 12, 10 ** 12)).map(lambda t: f"{t[0]}({t[1]}*pi/{t[2] or 1})" if t[0] != "root"
                                                       else f"root({t[1]}, {t[2]})"),
    st.integers(-10 ** 30, 10 ** 30).map(lambda k: f"2^{k}"))


def _fuzz(tmp_path_factory, entry: str, where: str) -> None:
    tmp = tmp_path_factory.mktemp("limits")
    path = system_file(tmp, entry) if where == "A" else system_file(tmp, "2", loss=entry)
    code, err = limited(cli.main, ["analyze", str(path)])
    assert_clean(code, err)
    code, err = limited(library, lambda: sk.IID([entry]))
    assert_clean(code, err)


@settings(max_examples=15, deadline=None)
@given(entry=ENTRY, where=st.sampled_from(["A", "loss"]))
def test_fuzz_under_limits(tmp_path_factory, entry, where):
    _fuzz(tmp_path_factory, entry, where)


@pytest.mark.full
@settings(max_examples=100, deadline=None,  # no shrinking: each case may take a minute
          phases=[Phase.explicit, Phase.reuse, Phase.generate])
@given(entry=ENTRY, where=st.sampled_from(["A", "loss"]))
def test_fuzz_under_limits_long(tmp_path_factory, entry, where):
    _fuzz(tmp_path_factory, entry, where)


def test_the_limits_are_real():
    """The harness itself: 4 GiB over the parent's size is refused inside the child (the case
    reports it as an untranslated MemoryError), so a real blow-up cannot reach the machine."""
    code, err = limited(library, lambda: bytearray(4 * 1024 ** 3))
    assert code == 70 and "MemoryError" in err
