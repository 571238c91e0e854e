"""The paper builds from the repository: its numbers from data/, and (where LaTeX is installed) its PDF.

* ``paper/scripts/make_numbers.py`` writes ``numbers.tex`` with every macro the paper uses,
  defined from the CSVs that are present (checked against the CSV itself for a few), and prints
  "n/a" with a warning, never a traceback, for inputs that are missing.
* The figures (``make_figures.py --quick``) and the coursework's table (``table_coursework.py``) are rebuilt
  into a temporary copy of ``paper/`` through ``BUBBLEOPTICS_FIGURES_DIR``: every ``fig_*.py``
  must write its PDF and PNG.
* With ``latexmk`` on the PATH that copy is built as ``paper/Makefile`` builds it, both PDFs twice
  (the main paper and its supplement read each other's labels through xr-hyper): each PDF must
  exist, resolve every citation and reference, have no overfull box, and (where ``pdffonts`` is
  installed) embed no Type 3 bitmap font; the main paper has at most ``MAX_PAGES`` pages.  Without
  LaTeX these tests are skipped (the Debian packages are named in ``paper/Makefile``).
* The abstract, parsed from ``paper.tex``, has at most ``MAX_ABSTRACT_WORDS`` words and quotes no
  ratio to the coursework's run times.

Nothing is written into the repository.
"""

import csv
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import paper_helpers

pytestmark = pytest.mark.api

ROOT = Path(__file__).resolve().parents[2]
PAPER = ROOT / "paper"
SCRIPTS = PAPER / "scripts"
MAKE_NUMBERS = SCRIPTS / "make_numbers.py"
DERIVED = ROOT / "data" / "derived"

#: The main paper's page limit and the abstract's word limit (issue 23).
MAX_PAGES = 12
MAX_ABSTRACT_WORDS = 250
#: The two documents, in the order paper/Makefile builds them.
DOCUMENTS = ("supplement", "paper")

#: Control words of paper.tex that start with a capital and are not numbers.tex macros: LaTeX's
#: own (section sign, Greek capitals, ...) and the paper's (\\R, \\T for reflectance, transmittance).
NOT_NUMBERS = {"IfFileExists", "PackageError", "DeclareTextSymbolDefault",
               "PackageWarning", "R", "T", "NumberNA", "S", "P", "L", "O", "AA",
               "AE", "OE", "TeX", "LaTeX", "Huge", "LARGE", "Large", "Delta", "Gamma", "Lambda", "Omega", "Phi",
               "Pi", "Psi", "Sigma", "Theta", "Upsilon", "Xi"}


def run(args, timeout, **kwargs):
    return subprocess.run([sys.executable, *map(str, args)], capture_output=True, text=True, timeout=timeout,
                          **kwargs)


def macros(path):
    """{name: text} of the \\newcommand lines of a numbers.tex."""
    text = Path(path).read_text(encoding="utf-8")
    return dict(re.findall(r"^\\newcommand\{\\([A-Za-z]+)\}\{(.*)\}$", text, flags=re.MULTILINE))


def declared_names():
    """Every macro make_numbers.py declares, from its SECTIONS table (``--list-macros``)."""
    result = run([MAKE_NUMBERS, "--list-macros"], timeout=60)
    assert result.returncode == 0, result.stderr
    return result.stdout.split()


def number(text):
    """The float of a plain-decimal macro value ('55\\,000' -> 55000.0)."""
    return float(text.replace(r"\,", ""))


@pytest.fixture(scope="module")
def numbers(tmp_path_factory):
    out = tmp_path_factory.mktemp("numbers") / "numbers.tex"
    result = run([MAKE_NUMBERS, "--out", out], timeout=120)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    return macros(out)


def test_every_declared_macro_is_written(numbers):
    names = declared_names()
    assert len(names) == len(set(names))
    assert sorted(numbers) == sorted(names)
    assert all(re.fullmatch(r"[A-Za-z]+", name) for name in names)


def test_every_number_in_the_paper_is_a_macro(numbers):
    used = set(re.findall(r"\\([A-Z][A-Za-z]*)", paper_helpers.source()))
    missing = sorted(used - NOT_NUMBERS - set(numbers))
    assert not missing, f"paper.tex uses macros that numbers.tex does not define: {missing}"


def test_no_number_is_na_with_the_repositorys_data(numbers):
    """Every input of make_numbers.py is in the repository, so no macro may fall back to n/a."""
    na = sorted(name for name, text in numbers.items() if "NumberNA" in text)
    assert not na, f"n/a with the repository's own data: {na}"


@pytest.mark.parametrize("path", sorted(DERIVED.glob("*.csv")), ids=lambda p: p.name)
def test_every_derived_csv_names_its_writer_machine_and_date(path):
    """The first line of each benchmark output is study.provenance's header: the
    script that wrote it, the date and the machine (what make_numbers.py reads back)."""
    first = path.read_text(encoding="utf-8").splitlines()[0]
    m = re.fullmatch(r"# written by (benchmarks/\w+\.py) on (\d{4}-\d{2}-\d{2}).*", first)
    assert m, f"{path.name}: no provenance header, first line {first[:80]!r}"
    assert (ROOT / m.group(1)).exists(), f"{path.name}: names {m.group(1)}, which does not exist"
    assert re.search(r"[(;] ?([^,();]+), (\d+) (cores?|CPUs)", first), f"{path.name}: no machine in {first!r}"


#: A number followed by a unit or a count noun (nm, µm, s, %, bands, pixels, ...): in the prose such a
#: number is a result, a setting or a constant of the code, so it must come from numbers.tex.
TYPED_WITH_UNIT = re.compile(
    r"(?<![\\\w{.])\d+(?:\.\d+)?(?:--\d+(?:\.\d+)?)?(?:\\,|~|\s)*"
    r"(?:nm\b|\\um|ms\b|ns\b|s\b|\\%|bands?\b|entries\b|samples?\b|pixels?\b|times\b|-fold|digits?\b|-digit)")


def prose(tex):
    """The text of the document body that is neither a comment, mathematics, nor a reference,
    citation, label or \\code{} argument."""
    body = tex[tex.index(r"\begin{document}"):]
    body = re.sub(r"(?<!\\)%.*", "", body)
    body = re.sub(r"\\begin\{(equation|align)\*?\}.*?\\end\{\1\*?\}", " ", body, flags=re.DOTALL)
    body = re.sub(r"\$[^$]*\$", " ", body)
    return re.sub(r"\\(ref|eqref|label|cite[pt]?|citealp|code)\*?(\[[^]]*\])?\{[^}]*\}", " ", body)


def test_prose_filter_finds_typed_numbers():
    tex = (r"\begin{document} with 421 bands (512 entries, 18.7\,nm) at 0.42\,\um{} in 3.2\,s, 7\,\%;"
           r" ok: \MaxBands{} bands, $16$ bands in math, listing~3.2, Fig.~\ref{fig:1} % 5 nm in a comment")
    found = [m.group(0) for m in TYPED_WITH_UNIT.finditer(prose(tex))]
    assert found == ["421 bands", "512 entries", "18.7\\,nm", "0.42\\,\\um", "3.2\\,s", "7\\,\\%"]


def test_no_number_with_a_unit_is_typed_in_the_prose(numbers):
    """Results, settings and constants in the text are macros (numbers.tex), not typed: no number
    with a unit or a count noun outside mathematics, and no machine name typed where a macro has it."""
    text = prose(paper_helpers.source())
    typed = sorted({m.group(0) for m in TYPED_WITH_UNIT.finditer(text)})
    assert not typed, f"typed numbers in paper.tex (make them macros of make_numbers.py): {typed}"
    for name, value in numbers.items():
        if name.endswith("Machine") and "NumberNA" not in value:
            assert value.replace(r"\_", "_") not in text.replace(r"\_", "_"), f"{value!r} typed; use \\{name}"


@pytest.mark.skipif(not (DERIVED / "bandlimited_colour.csv").exists(), reason="no data/derived/bandlimited_colour.csv")
def test_one_exposure_convention_for_film_colours(numbers):
    """Figs. bandlimited and stability quote the same point-sampling error for the same case (16
    bands, normal incidence, D65, water, 0-20 um) only if both use the same exposure: the two
    benchmarks' maxima agree (their thickness grids differ, hence the tolerance), and the band-limited
    colour's maxima too."""
    assert number(numbers["AliasMaxAllSixteen"]) == pytest.approx(number(numbers["BlPointSixteenMaxNormal"]), rel=0.1)
    assert number(numbers["BandlimitedMaxSixteen"]) == pytest.approx(number(numbers["BlSixteenMaxNormal"]), rel=0.1)
    assert number(numbers["BlExposedGainMin"]) > 1  # the exposed differences are the larger ones


@pytest.mark.skipif(not (DERIVED / "optics_speed.csv").exists(), reason="no data/derived/optics_speed.csv")
def test_optics_numbers_come_from_the_csv(numbers):
    lines = [ln for ln in (DERIVED / "optics_speed.csv").read_text().splitlines() if not ln.startswith("#")]
    rows = list(csv.DictReader(lines))
    colour = next(r for r in rows if "thin_film_tmm" in r["implementation"])
    ours = {r["threads"]: r for r in rows if r["case"] == "sweep" and r["implementation"].startswith("bubbleoptics")}
    assert sorted(ours) == ["1", "2"] and colour["threads"] == "1"  # ours with one and two threads, peers one
    # like for like: the plain macros are ours with one thread and the peers' ratios to it
    assert number(numbers["SpeedupColour"]) == pytest.approx(float(colour["ratio_to_bubbleoptics"]), rel=0.01)
    assert number(numbers["NsOurs"]) == pytest.approx(float(ours["1"]["ns_per_evaluation"]), rel=0.05)
    assert number(numbers["NsOursTwo"]) == pytest.approx(float(ours["2"]["ns_per_evaluation"]), rel=0.05)
    assert number(numbers["SpeedupColourTwo"]) == pytest.approx(float(colour["ratio_to_bubbleoptics_2_threads"]),
                                                                rel=0.01)
    assert number(numbers["OursThreadSpeedup"]) == pytest.approx(float(ours["1"]["ratio_to_bubbleoptics_2_threads"]),
                                                                 abs=0.06)
    assert "NumberNA" not in "".join(v for k, v in numbers.items() if k.startswith(("Sweep", "Ns", "Speedup")))


@pytest.mark.skipif(not (DERIVED / "coursework_table.csv").exists(), reason="no data/derived/coursework_table.csv")
def test_coursework_table_numbers_come_from_the_csvs(numbers):
    lines = (ROOT / "data" / "coursework_table_4_1.csv").read_text().splitlines()
    rows = list(csv.DictReader(ln for ln in lines if not ln.startswith("#")))
    growth = float(rows[-1]["one_bubble"]) / float(rows[0]["one_bubble"])
    assert number(numbers["CourseworkGrowthOne"]) == pytest.approx(growth, rel=0.01)
    assert numbers["CourseworkBestIsAffine"] in ("0", "1")
    for name in ("OursDepthOneMin", "OursDepthTenMax", "SpeedupDepthTenMax", "RaysGrowthExhaustiveOne"):
        assert number(numbers[name]) > 0


def test_missing_inputs_give_na_and_a_warning_not_a_crash(tmp_path):
    out = tmp_path / "numbers.tex"
    empty = tmp_path / "no-data"
    empty.mkdir()
    result = run([MAKE_NUMBERS, "--out", out, "--data", empty], timeout=120)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    assert "warning" in result.stderr and "optics_speed.csv" in result.stderr
    written = macros(out)
    assert sorted(written) == sorted(declared_names())
    for name in ("SpeedupColour", "CourseworkGrowthOne", "OursDepthOneMin", "GrazingOursRelT", "AliasOnsetSixteen"):
        assert written[name] == r"\NumberNA{}", name
    assert r"\providecommand{\NumberNA}" in out.read_text()


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """A copy of paper/ with its figures (quick mode), the coursework's table and numbers.tex, all
    written by the repository's scripts into a temporary folder (BUBBLEOPTICS_FIGURES_DIR)."""
    build = tmp_path_factory.mktemp("paper")
    for name in ("paper.tex", "supplement.tex", "preamble.tex", "references.bib"):
        shutil.copy(PAPER / name, build / name)
    shutil.copytree(PAPER / "sections", build / "sections")
    env = dict(os.environ, BUBBLEOPTICS_FIGURES_DIR=str(build / "figures"), MPLBACKEND="Agg")
    if (SCRIPTS / "make_figures.py").exists():  # the session's one quick build, shared with test_paper_figures
        figures, returncode, output = paper_helpers.quick_figures(tmp_path_factory)
        assert returncode == 0, output[-4000:]
        shutil.copytree(figures, build / "figures")
    if (SCRIPTS / "table_coursework.py").exists():
        result = run([SCRIPTS / "table_coursework.py"], timeout=60, env=env)
        assert result.returncode == 0, result.stderr[-2000:]
    result = run([MAKE_NUMBERS, "--out", build / "numbers.tex"], timeout=120)
    assert result.returncode == 0, result.stderr[-2000:]
    return build


def test_figures_and_table_build_in_quick_mode(built):
    """Every fig_*.py writes its PDF and PNG; table_coursework.py writes a booktabs tabular."""
    for script in sorted(SCRIPTS.glob("fig_*.py")):
        for suffix in (".pdf", ".png"):
            assert (built / "figures" / f"{script.stem}{suffix}").stat().st_size > 0, script.name
    table = (built / "figures" / "table_coursework.tex").read_text(encoding="utf-8")
    assert table.count(r"\\") >= 13 and r"\toprule" in table and r"\bottomrule" in table


def _pages(pdf, log):
    if shutil.which("pdfinfo"):
        info = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, timeout=30).stdout
        m = re.search(r"^Pages:\s+(\d+)", info, flags=re.MULTILINE)
        if m:
            return int(m.group(1))
    try:
        import pypdf

        return len(pypdf.PdfReader(str(pdf)).pages)
    except ImportError:
        pass
    m = re.search(r"Output written on \S+ \((\d+) pages?", log)
    if m:
        return int(m.group(1))
    return len(re.findall(rb"/Type\s*/Page\b", pdf.read_bytes()))


@pytest.fixture(scope="module")
def pdfs(built):
    """{document: (pdf, log)} of both PDFs built as paper/Makefile builds them: each once, then each
    again with -g once both .aux files exist (each document reads the other's labels)."""
    for force in ([], ["-g"]):
        for doc in DOCUMENTS:
            latex = subprocess.run(["latexmk", "-pdf", "-interaction=nonstopmode", "-halt-on-error", *force,
                                    f"{doc}.tex"], cwd=built, capture_output=True, text=True, timeout=300)
            log = (built / f"{doc}.log").read_text(errors="replace") if (built / f"{doc}.log").exists() else ""
            assert latex.returncode == 0, f"{doc}: " + latex.stdout[-3000:] + log[-3000:]
    return {doc: (built / f"{doc}.pdf", (built / f"{doc}.log").read_text(errors="replace")) for doc in DOCUMENTS}


def log_problems(log):
    """The problems of a LaTeX log that the paper must not have: unresolved citations and
    references, overfull boxes and labels or citations defined twice (e.g. by both documents)."""
    problems = re.findall(r"Citation `[^']*' .*undefined", log)
    problems += re.findall(r"Reference `[^']*' .*undefined", log)
    problems += ["There were undefined references"] if "There were undefined references" in log else []
    problems += re.findall(r"^Overfull \\[hv]box .*$", log, flags=re.MULTILINE)
    problems += re.findall(r"(?:Label|Citation) `[^']*' multiply defined", log)
    return problems


def test_log_problems_are_found():
    log = ("LaTeX Warning: Reference `sec:core' on page 3 undefined on input line 7.\n"
           "Package natbib Warning: Citation `Huang2020' on page 2 undefined on input line 9.\n"
           "Overfull \\hbox (3.1pt too wide) in paragraph at lines 5--6\n"
           "Package natbib Warning: Citation `Blender' multiply defined.\n"
           "LaTeX Warning: There were undefined references.\n")
    assert len(log_problems(log)) == 5
    assert log_problems("Output written on paper.pdf (12 pages, 1 bytes).\nUnderfull \\hbox (badness 10000)\n") == []


@pytest.mark.skipif(shutil.which("latexmk") is None, reason="LaTeX not installed")
@pytest.mark.parametrize("doc", DOCUMENTS)
def test_pdf_builds_clean(pdfs, doc):
    """Both PDFs: built, every citation and cross-reference (within and between them) resolved, no
    overfull box, no Type 3 font."""
    pdf, log = pdfs[doc]
    assert pdf.exists() and _pages(pdf, log) > 1
    problems = log_problems(log)
    assert not problems, f"{doc}.log: {problems[:5]}"
    if shutil.which("pdffonts"):  # poppler-utils: a Type 3 font is a bitmap (e.g. a TS1 glyph without cm-super)
        fonts = subprocess.run(["pdffonts", str(pdf)], capture_output=True, text=True, timeout=60)
        assert fonts.returncode == 0, fonts.stderr
        type3 = [line for line in fonts.stdout.splitlines()[2:] if "Type 3" in line]
        assert not type3, f"{doc}.pdf embeds Type 3 (bitmap) fonts: {type3}"


@pytest.mark.skipif(shutil.which("latexmk") is None, reason="LaTeX not installed")
def test_main_paper_fits_its_page_limit(pdfs):
    pdf, log = pdfs["paper"]
    pages = _pages(pdf, log)
    assert 3 < pages <= MAX_PAGES, f"paper.pdf has {pages} pages, the limit is {MAX_PAGES}"


@pytest.mark.skipif(shutil.which("latexmk") is None, reason="LaTeX not installed")
def test_the_two_pdfs_refer_to_each_other(pdfs):
    """The supplement's sections are numbered S1, S2, ... and the main paper cites them by those
    numbers; the supplement refers back to the main paper's sections."""
    _, paper_log = pdfs["paper"]
    aux = (pdfs["paper"][0].with_suffix(".aux")).read_text(errors="replace")
    supplement_aux = (pdfs["supplement"][0].with_suffix(".aux")).read_text(errors="replace")
    assert re.search(r"\\newlabel\{sec:coursework\}\{\{S\d+\}", supplement_aux)
    assert not re.search(r"\\newlabel\{sec:physics\}\{\{S", aux)
    text = subprocess.run(["pdftotext", str(pdfs["paper"][0]), "-"], capture_output=True, text=True,
                          timeout=60).stdout if shutil.which("pdftotext") else "Supplement \u00a7S1"
    assert re.search(r"Supplement\s*(\u00a7|Fig\.)\s*S\d", text)


def abstract_words(tex):
    """The words of the abstract of *tex* (a paper.tex): comments dropped, each inline formula and
    each macro (a number of numbers.tex) one word, braces and ties as spaces."""
    m = re.search(r"\\begin\{abstract\}(.*?)\\end\{abstract\}", tex, flags=re.DOTALL)
    if not m:
        raise ValueError("paper.tex has no abstract environment")
    body = re.sub(r"(?<!\\)%.*", "", m.group(1))
    body = re.sub(r"\$[^$]*\$", " FORMULA ", body)
    body = re.sub(r"\\[,;:!]", "", body)  # thin spaces glue a number to its unit
    body = re.sub(r"\\(textsf|emph|textit|textbf|code)\{([^}]*)\}", r" \2 ", body)
    body = re.sub(r"\\[A-Za-z]+(\{\})?", " MACRO ", body)
    body = body.replace("~", " ").replace("{", " ").replace("}", " ")
    return [w for w in body.split() if re.search(r"\w", w)]


def test_abstract_word_counter():
    tex = (r"\begin{abstract} A film, \NsOurs\,ns long; $\Delta E_{00}=1$ % a comment"
           "\n Mitsuba~3 and \\textsf{tmm} -- done.\\end{abstract}")
    assert abstract_words(tex) == ["A", "film,", "MACRO", "long;", "FORMULA", "Mitsuba", "3", "and", "tmm", "done."]
    with pytest.raises(ValueError):
        abstract_words("no abstract here")


def test_abstract_is_short_and_quotes_no_coursework_ratio():
    """At most MAX_ABSTRACT_WORDS words; the ratios to the coursework's times (another machine,
    program and, for the thin-film chain, another tree) belong in the supplement, not the abstract."""
    tex = (PAPER / "paper.tex").read_text(encoding="utf-8")
    words = abstract_words(tex)
    assert 100 < len(words) <= MAX_ABSTRACT_WORDS, f"abstract has {len(words)} words"
    abstract = re.search(r"\\begin\{abstract\}(.*?)\\end\{abstract\}", tex, flags=re.DOTALL).group(1)
    ratios = re.findall(r"\\(SpeedupDepth\w+|TwoSphereSpeedup\w+|OursDepth\w+|CourseworkDepth\w+)", abstract)
    assert not ratios, f"the abstract quotes the coursework comparison: {ratios}"
