"""Shared helpers of the command-line tests: run ``tracer`` in this process and check its stderr."""

from tracer.cli import main


def run(argv, capsys):
    """``tracer ARGV`` in-process: (exit status, stdout, stderr).  argparse exits via SystemExit."""
    try:
        status = main([str(a) for a in argv])
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    return status, out, err


def assert_one_line(err):
    """Exactly one line on stderr and no Python traceback."""
    assert err.endswith("\n") and err.count("\n") == 1, repr(err)
    assert "Traceback" not in err and "File \"" not in err, err
