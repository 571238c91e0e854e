"""The tolerances the repository states, a plug-in of ``make_numbers.py``.

* ``documented``: tolerances the test suite enforces, read from the sentences of ``README.md``
  and the test modules' docstrings that state them (so the paper quotes what the repository
  says, and a changed bar shows up as n/a rather than as a stale number).
"""

from __future__ import annotations

import re

from macros import sci_or_plain, scientific

#: where these macros stand in numbers.tex (make_numbers.py)
ORDER = 10


_NUM = r"([0-9][0-9.]*(?:e[-+]?[0-9]+)?)"


def documented(dirs):
    """Tolerances stated (and enforced) by the repository, read from the sentences stating them."""
    root = dirs["root"]
    readme = (root / "README.md").read_text(encoding="utf-8")
    out = {}
    m = re.search(rf"within \*\*{_NUM} absolute and {_NUM} relative\*\*", readme)
    if not m:
        raise ValueError("README.md: the accuracy sentence ('within **A absolute and B relative**') is gone")
    out["AccBarAbs"], out["AccBarRel"] = scientific(float(m.group(1)), 1), scientific(float(m.group(2)), 1)
    m = re.search(rf"measured worst: {_NUM} and {_NUM}", readme)
    if not m:
        raise ValueError("README.md: the sentence 'measured worst: A and B' is gone")
    out["AccWorstAbs"], out["AccWorstRel"] = scientific(float(m.group(1)), 1), scientific(float(m.group(2)), 1)
    bench = (root / "benchmarks" / "optics_speed.py").read_text(encoding="utf-8")
    m = re.search(r"Sweep: (\d+) wavelengths \((\d+)-(\d+) nm every \d+ nm\) x (\d+) angles .*?x (\d+) thicknesses",
                  bench, flags=re.DOTALL)
    if not m:
        raise ValueError("benchmarks/optics_speed.py: the sentence 'Sweep: N wavelengths (A-B nm ...) x ...' is gone")
    (out["SweepWavelengths"], out["SweepWlMin"], out["SweepWlMax"], out["SweepAngles"],
     out["SweepThicknesses"]) = m.groups()
    tests = root / "tests"
    text = (tests / "bubbleoptics" / "test_reference_mpmath.py").read_text(encoding="utf-8")
    m = re.search(r"wavelength (\d+)-(\d+) nm, thickness\s+0-(\d+) µm.*?angle 0 \.\. pi/2 - 1e-(\d+).*?"
                  r"film\s+n ([\d.]+)-([\d.]+) with k 0 or up to ([\d.]+)", text, flags=re.DOTALL)
    if not m:
        raise ValueError("tests/bubbleoptics/test_reference_mpmath.py: the domain sentence "
                         "('wavelength A-B nm, thickness 0-C µm ..., angle 0 .. pi/2 - 1eD ..., "
                         "film n E-F with k 0 or up to G') is gone")
    (out["RefDomainWlMin"], out["RefDomainWlMax"], out["RefDomainThicknessUm"], out["RefDomainGrazingExp"],
     out["RefDomainIndexMin"], out["RefDomainIndexMax"], out["RefDomainKMax"]) = m.groups()
    patterns = {
        "TmmTol": ("bubbleoptics/test_reference_tmm.py", rf"\|ours - tmm\| <= {_NUM}"),
        "ColourXYZTol": ("bubbleoptics/test_colorimetry.py", rf"/ 100 to {_NUM}"),
        "FilmColourTol": ("bubbleoptics/test_colorimetry.py", rf"film_color within {_NUM} per channel"),
        "HypothesisExamples": ("conftest.py", r"max_examples=([0-9]+)"),
    }
    for name, (file, pattern) in patterns.items():
        text = (tests / file).read_text(encoding="utf-8")
        m = re.search(pattern, text)
        if not m:
            raise ValueError(f"tests/{file}: no match for {pattern!r}")
        value = float(m.group(1))
        out[name] = str(int(value)) if name == "HypothesisExamples" else sci_or_plain(value, 1)
    return out


DOCUMENTED_MACROS = ["RefDomainWlMin", "RefDomainWlMax", "RefDomainThicknessUm", "RefDomainGrazingExp",
                     "RefDomainIndexMin", "RefDomainIndexMax", "RefDomainKMax", "SweepWavelengths", "SweepWlMin",
                     "SweepWlMax", "SweepAngles", "SweepThicknesses", "AccBarAbs", "AccBarRel", "AccWorstAbs",
                     "AccWorstRel", "TmmTol", "ColourXYZTol", "FilmColourTol", "HypothesisExamples"]

SECTIONS = {
    "documented": (["README.md", "tests/"], documented, DOCUMENTED_MACROS),
}
