"""The command line's argument types (gd_analyze.cli.parsing): a value out of its range is
one line naming the option and the value given, exit status 2, before any file is read."""

import pytest

from gd_analyze.cli import main


@pytest.mark.parametrize("argv, line", [
    (["--payload-com", "1,2"],
     "argument --payload-com: --payload-com needs 3 comma-separated numbers, got '1,2'"),
    (["--gravity=-9.81,0"],
     "argument --gravity: --gravity needs 3 comma-separated numbers, got '-9.81,0'"),
    (["--qd-max", "1,0"], "argument --qd-max: --qd-max limits must be at least 1e-09, got '1,0'"),
    # a denormal limit overflowed the plan's duration ("overflow encountered in divide"), and
    # the excitation's regressor (scaled condition number inf, exit 0)
    (["--qd-max", "1e-320"],
     "argument --qd-max: --qd-max limits must be at least 1e-09, got '1e-320'"),
    (["--qdd-max", "1,1e-10"],
     "argument --qdd-max: --qdd-max limits must be at least 1e-09, got '1,1e-10'"),
    (["--tolerance=-0.5"], "argument --tolerance: --tolerance must be in [0.0, 1000.0], got -0.5"),
    # EPS x s_i overflowed to inf in the region search (exit 0 after overflow warnings)
    (["--tolerance", "1e308"],
     "argument --tolerance: --tolerance must be in [0.0, 1000.0], got 1e+308"),
    (["--payload", "-1"], "argument --payload: --payload must be in [0.0, inf), got -1.0"),
    (["--qdd-max", "1,x"],
     "argument --qdd-max: expected comma-separated numbers, got '1,x': "),
])
def test_a_bad_value_is_one_line_naming_the_option(capsys, argv, line):
    code = main(["puma560", "no-such-file.csv", *argv])
    err = capsys.readouterr().err
    assert code == 2
    assert err.startswith(f"gd-analyze: error: {line}") and err.count("\n") == 1


@pytest.mark.parametrize("value, ok", [("0.01", (0.01, 0.01)), ("0.01,0.002", (0.01, 0.002)),
                                       ("0", None), ("1,2,3", None), ("2000", None)])
def test_the_verdict_tolerance_takes_one_or_two_numbers_in_range(capsys, value, ok):
    from gd_analyze.cli.parsing import control_parser

    if ok is not None:
        args = control_parser().parse_intermixed_args(
            ["m.json", "t.csv", f"--verdict-tolerance={value}"])
        assert args.verdict_tolerance == ok
        return
    code = main(["control", "m.json", "t.csv", f"--verdict-tolerance={value}"])
    err = capsys.readouterr().err
    assert code == 2 and err == ("gd-analyze: error: control: argument --verdict-tolerance: "
                                 "--verdict-tolerance needs 1 or 2 numbers in (0, 1e3], got "
                                 f"{value!r}\n")


@pytest.mark.parametrize("argv, said", [
    (["--drives", "armature,armature"], "a drive column given twice in 'armature,armature'"),
    (["--current", "--drive-gains", "1e308,1"], "at most 1e6 N m/A in size"),
])
def test_identify_drive_options_out_of_range_are_one_line(capsys, argv, said):
    """A drive column named twice was an internal error (exit 4); a drive gain near a float's
    range overflowed the torques (warnings, then "SVD did not converge")."""
    code = main(["identify", "two-link", "no-such-file.csv", *argv])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and said in err, err


@pytest.mark.parametrize("workers, ok", [("1", True), ("256", True), ("257", False),
                                         ("1000", False), ("0", False)])
def test_sweep_workers_are_at_most_256(workers, ok):
    """--workers 1000 started a LocalCluster of 1000 processes on this machine. The parser
    alone is asked: the old one let the value through, and a sweep would have started them."""
    from gd_analyze.cli.parsing import sweep_parser
    from gd_analyze.errors import InputError

    argv = ["puma560", "--random", "2", "--workers", workers]
    if ok:
        assert sweep_parser().parse_intermixed_args(argv).workers == int(workers)
        return
    with pytest.raises(InputError, match=rf"^sweep: argument --workers: --workers must be in "
                                         rf"\[1, 256\], got {workers}$"):
        sweep_parser().parse_intermixed_args(argv)


@pytest.mark.parametrize("argv, line", [
    # ran with exit 0: Kp = 1e-600 underflows to 0, a controller that does not control
    (["--wn", "1e-300"], "--wn must be in [0.01, 10000.0], got 1e-300"),
    (["--wn", "2e4"], "--wn must be in [0.01, 10000.0], got 20000.0"),
    # was refused as too stiff with "its fastest mode, inf rad/s" (zeta^2 overflowed)
    (["--zeta", "1e300"], "--zeta must be in [0.01, 100.0], got 1e+300"),
    (["--zeta", "0.001"], "--zeta must be in [0.01, 100.0], got 0.001"),
])
def test_control_gains_out_of_range_are_one_line(capsys, argv, line):
    """wn and zeta beyond the controllers a drive could follow: one line naming the option
    and the range, before the model or the trajectory is read."""
    code = main(["control", "no-such-model.json", "no-such-file.csv", *argv])
    err = capsys.readouterr().err
    assert code == 2 and err == f"gd-analyze: error: control: argument {argv[0]}: {line}\n", err


@pytest.mark.parametrize("argv", [["--wn", "0.01", "--zeta", "100"], ["--wn", "1e4",
                                                                        "--zeta", "0.01"]])
def test_control_gains_at_their_bounds_are_taken(argv):
    from gd_analyze.cli.parsing import control_parser

    args = control_parser().parse_intermixed_args(["m.json", "t.csv", *argv])
    assert (args.wn, args.zeta) == (float(argv[1]), float(argv[3]))
