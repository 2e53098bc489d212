"""The documentation site: it builds with warnings as errors, every internal link resolves, and every public
name of ``armlab`` has an entry in its API reference.

The build is the one ``make docs`` runs (docs/conf.py), from a copy of ``docs/`` and the README in a temporary
folder (the generated pages go there, not into the repository), on the session's fast reproduction. The
notebooks are not executed here (``nb_execution_mode=off``): tests/test_notebooks.py executes each of them.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

import armlab

#: The build (with the session's reproduction, when this module is the first to need it) takes minutes on a busy
#: machine: more than the suite's 300 s default per test.
pytestmark = pytest.mark.timeout(1200)

ROOT = Path(__file__).resolve().parent.parent


class _Links(HTMLParser):
    """The ids a page defines and the links (href, src) it holds."""

    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.links: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if name in ("id", "name") and value:
                self.ids.add(value)
            if name in ("href", "src") and value:
                self.links.append(value)


def _parse(path: Path) -> _Links:
    parser = _Links()
    parser.feed(path.read_text(errors="replace"))
    return parser


@pytest.fixture(scope="module")
def site(tmp_path_factory, reproduction):
    """The built site's folder (``docs/_build``'s html), built once for this module."""
    out, _, _ = reproduction
    work = tmp_path_factory.mktemp("docs")
    shutil.copytree(ROOT / "docs", work / "docs", ignore=shutil.ignore_patterns("_generated", "_build"))
    shutil.copy(ROOT / "README.md", work / "README.md")
    html = work / "html"
    env = dict(os.environ, ARMLAB_DOCS_ROOT=str(ROOT), ARMLAB_DOCS_REPRODUCTION=str(out))
    done = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-q", "-D", "nb_execution_mode=off",
                           "-b", "html", str(work / "docs"), str(html)], env=env, capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-3000:]
    return html


@pytest.mark.slow
def test_every_internal_link_resolves(site):
    pages = sorted(site.rglob("*.html"))
    assert len(pages) > 20
    parsed = {page: _parse(page) for page in pages}
    broken = []
    for page, links in parsed.items():
        for link in links.links:
            parts = urlsplit(link)
            if parts.scheme or link.startswith("//") or link.startswith("data:"):
                continue
            target = (page.parent / unquote(parts.path)).resolve() if parts.path else page
            if not target.exists():
                broken.append(f"{page.relative_to(site)}: {link} (no file)")
            elif parts.fragment and target.suffix == ".html":
                ids = parsed[target].ids if target in parsed else _parse(target).ids
                if unquote(parts.fragment) not in ids:
                    broken.append(f"{page.relative_to(site)}: {link} (no anchor)")
    assert not broken, "\n".join(broken[:40])


@pytest.mark.slow
def test_every_public_name_has_an_api_entry(site):
    from sphinx.util.inventory import InventoryFile

    with open(site / "objects.inv", "rb") as f:
        inventory = InventoryFile.load(f, "", os.path.join)
    documented = {name for entries in inventory.values() for name in entries}
    missing = [name for name in armlab.__all__ if not name.startswith("__") and f"armlab.{name}" not in documented]
    assert not missing, missing
    # and the modules of the subpackages each have their page
    for module in ("armlab.models.arm", "armlab.kinematics.rnea", "armlab.models.plant", "armlab.drives.train"):
        assert (site / "_generated" / "api" / f"{module}.html").exists(), module


@pytest.mark.slow
def test_paper_pages_hold_the_reports_verdicts_and_figures(site):
    for paper in ("000", "001", "003", "004"):
        page = site / "_generated" / "papers" / f"{paper}.html"
        text = page.read_text()
        assert "matches" in text and "paper value" in text, paper
        images = [src for src in _parse(page).links if re.search(r"\.(png|svg)$", src)]
        assert images, f"paper {paper}'s page shows no figure"


@pytest.mark.slow
def test_math_is_rendered_offline(site):
    """The notebooks' and the report's mathematics is inline SVG: the pages load no MathJax or other script from
    the network."""
    page = (site / "_generated" / "notebooks" / "01_paper000_rr_arm.html").read_text()
    assert '<span class="math"><svg' in page or '<span class="math"><span' in page
    for path in site.rglob("*.html"):
        for link in _parse(path).links:
            assert not (link.startswith("http") and link.endswith(".js")), f"{path.name} loads {link}"


def test_the_cli_reference_is_generated_from_the_parser(tmp_path, monkeypatch, capsys):
    """Issue 33: no CLI reference (options such as ``plan --motor-torque`` were only in ``--help``). docs/pages.py
    writes one page per command of the CLI's own parser, its ``--help`` text as ``armlab COMMAND --help`` prints it,
    and an index of every command."""
    import importlib.util

    from armlab.cli import main

    spec = importlib.util.spec_from_file_location("docs_pages", ROOT / "docs" / "pages.py")
    pages = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(pages)
    pages.write_cli(tmp_path)
    index = (tmp_path / "cli" / "index.md").read_text()
    names = list(pages.commands())
    assert {"plan", "simulate", "export", "size", "workspace"} <= set(names)
    monkeypatch.setenv("COLUMNS", str(pages.HELP_WIDTH))
    for name in names:
        assert f"[`armlab {name}`]({name}.md)" in index
        assert main([name, "--help"]) == 0
        printed = capsys.readouterr().out
        assert f"```text\n{printed}```" in (tmp_path / "cli" / f"{name}.md").read_text(), name
    assert "--motor-torque" in (tmp_path / "cli" / "plan.md").read_text()


def test_paper_pages_lead_with_what_a_user_does(tmp_path, monkeypatch):
    """Issue 33: paper pages opened with module autodoc. Each now opens with what a user does with the paper's arms
    (commands the CLI's parser takes, then the Python), then the report, then the modules' reference."""
    import importlib.util
    import shlex

    from armlab.cli import build_parser

    spec = importlib.util.spec_from_file_location("docs_pages", ROOT / "docs" / "pages.py")
    pages = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(pages)
    given = tmp_path / "given"
    given.mkdir()
    (given / "report.md").write_text("".join(f"## Paper {p}: {t}\n\nverdicts of {p}\n\n" for p, (t, _, _) in
                                             pages.PAPERS.items()))
    monkeypatch.setenv("ARMLAB_DOCS_REPRODUCTION", str(given))
    pages.write_papers(tmp_path / "site")
    for paper, (_, arms, _) in pages.PAPERS.items():
        page = (tmp_path / "site" / "papers" / f"{paper}.md").read_text()
        lead, report, reference = (page.index(h) for h in ("## What you do with it", "## The report",
                                                           "## Reference: the paper's arm"))
        assert lead < report < reference and page.index(".. automodule::") > reference
        assert f"verdicts of {paper}" in page[report:reference]
        block = page[lead:report].split("```text\n")[1].split("```")[0]
        commands = [shlex.split(line.split("#")[0])[1:] for line in block.splitlines()]
        assert commands[0][:2] == ["reproduce", "--paper"] and all(any(a in c for c in commands) for a in arms)
        for argv in commands:
            build_parser().parse_args(argv)  # every command is one the CLI takes (SystemExit otherwise)


@pytest.mark.slow
def test_the_arm_entry_opens_with_what_a_user_does(site):
    """Issue 33: the API page's ``Arm`` opened with its 25 constructor fields; its entry now opens with its
    docstring (``armlab.load(…)``), the constructor left out of the heading."""
    page = (site / "_generated" / "api" / "index.html").read_text()
    start = page.index('id="armlab.Arm"')
    heading = page[start:page.index("</dt>", start)]
    assert "bodies" not in heading and "urdf_file" not in heading
    assert "armlab.load(" in html_text(page[start:start + 4000])


def html_text(fragment: str) -> str:
    """The text of an HTML fragment (tags dropped, entities unescaped)."""
    import html

    return html.unescape(re.sub(r"<[^>]+>", "", fragment))


@pytest.mark.slow
def test_the_mathematics_keeps_its_size_on_the_site(site):
    """Issue 33: paper 000's T04 matrix was unreadable on the site (its SVG pieces shrunk by the theme's
    ``img{max-width:100%}`` in narrow matrix cells, with no grid style): every page now carries the report's own
    math style (armlab.papers.math_html.MATH_CSS), the pieces at their own size, the matrix a bracketed grid."""
    from armlab.papers.math_html import MATH_CSS

    page = (site / "_generated" / "papers" / "000.html").read_text()
    assert 'table class="mat"' in page and f"<style>{MATH_CSS}</style>" in page
    assert "max-width:none" in MATH_CSS and "table.mat{" in MATH_CSS


def test_the_builds_notebook_kernels_talk_over_ipc():
    """``make docs`` executes the notebooks (MyST-NB, which gives its kernel manager no options): docs/conf.py makes
    their kernels talk over IPC, so no TCP port is opened and ipykernel prints no warning of an unencrypted one per
    notebook (issue 33: four of them in every build)."""
    code = ("import runpy, sys; runpy.run_path(sys.argv[1]); from jupyter_client.manager import KernelManager; "
            "print(KernelManager(kernel_name='python3').transport)")
    done = subprocess.run([sys.executable, "-c", code, str(ROOT / "docs" / "conf.py")], capture_output=True, text=True,
                          timeout=120, cwd=ROOT / "docs")
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.splitlines()[-1] == "ipc"
