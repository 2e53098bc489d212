"""The generated pages of the documentation site: the API reference, one page per paper, the notebooks.

* ``api/`` — every public name of ``armlab`` (its ``__all__``) with its docstring, and one page per module
  of the subpackages (the docstrings carry each method's equations, units and shapes);
* ``papers/NNN.md`` — what a user does with the paper's arms (the commands, the Python), then the paper's section
  of a fresh ``armlab reproduce --fast`` report (its verdicts, tables and figures), then the docstrings of the
  paper's arm and method modules;
* ``notebooks/`` — copies of the repository's notebooks, executed by MyST-NB in the build;
* ``cli/`` — the CLI reference: one page per ``armlab`` command, its ``--help`` as the parser itself prints it
  (no hand-written copy to fall behind the options).

Everything is written into a folder that the build owns (``docs/_generated``, not committed).
"""

from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import re
import shutil
from pathlib import Path

#: The repository (the folder holding ``notebooks/`` and ``README.md``); ``ARMLAB_DOCS_ROOT`` overrides it.
ROOT = Path(os.environ.get("ARMLAB_DOCS_ROOT", Path(__file__).resolve().parent.parent))

#: The subpackages whose modules get an API page each, with a line saying what they hold.
SUBPACKAGES = {  # in the order of the rooms (README's layout)
    "armlab.kinematics": "one module per method: each paper's formulation, IK, inverse dynamics, trajectories",
    "armlab.drives": "drive trains: gear ratio, rotor inertia, efficiency, friction, motor electrics",
    "armlab.models": "the arms (one module per paper arm), the readers of users' own arms, the plant builder",
    "armlab.models.library": "well-known arms by name, one module each, their numbers' sources cited",
    "armlab.collision": "collision geometry, scenes and clearances",
    "armlab.presentation": "the pictures: plots, drawings, graphviz files, the replay and the viewer",
    "armlab.planning": "motions to run and their fastest timing",
    "armlab.controllers": "the inverse-dynamics controller and the servo loop: controllers, sensors, current loops",
    "armlab.diagrams": "the Drake Systems diagram of a run and its simulation",
    "armlab.sizing": "drive sizing: catalogues, duty cycles, load cases, the selection and the vendors' checks",
    "armlab.analysis": "workspaces, singular configurations and design studies",
}

#: The paper pages: number → (title, its arms, the modules whose docstrings give its arm and its equations).
PAPERS = {
    "000": ("Hroncová et al., Robot trajectory planning (2022): the RR and RRRR arms", ("rr", "rrrr"),
            ["armlab.models.rr", "armlab.models.rrrr", "armlab.kinematics.basic_movements", "armlab.kinematics.dh",
             "armlab.kinematics.quintic"]),
    "001": ("Qin et al., Four degree of freedom manipulator's kinematics simulation analysis based on MATLAB",
            ("arm4r",), ["armlab.models.arm4r", "armlab.kinematics.ik_closed_form"]),
    "003": ("Schonstein & Panc, Kinematical modelling for R2T serial structure (2017)", ("r2t",),
            ["armlab.models.r2t", "armlab.kinematics.locating", "armlab.kinematics.iterative"]),
    "004": ("Ondočko et al., Position forward kinematics of 6-DOF robotic arm", ("urm6",),
            ["armlab.models.urm6", "armlab.kinematics.urm"]),
}


def paper_lead(paper: str, arms: tuple[str, ...]) -> str:
    """A paper page's opening: what a user does with the paper's arms (the commands, then the Python)."""
    pairs = [(f"armlab reproduce --paper {paper} --out out", "the paper's figures and tables beside armlab's: "
              "out/report.md")]
    for arm in arms:
        pairs += [(f"armlab show {arm}", "its joints, parameters and their sources"),
                  (f"armlab simulate {arm} --out runs/{arm}", "the paper's motion through Fig. 6's diagram"),
                  (f"armlab draw {arm} --out {arm}.png", "its kinematic scheme")]
    width = max(len(command) for command, _ in pairs) + 2
    lines = [f"{command.ljust(width)}# {what}" for command, what in pairs]
    first = arms[0]
    return ("## What you do with it\n\n```text\n" + "\n".join(lines) + "\n```\n\n"
            f"In Python: `arm = armlab.load(\"{first}\")`, then `armlab.simulate(arm, armlab.paper_motion(arm))`, "
            "`armlab.draw(arm)`, `arm.fk(q)`; the report below is what `armlab reproduce` writes, the reference "
            "after it the arm's and the method's modules.\n\n")


def armlab_version() -> str:
    """The installed armlab's version."""
    import armlab

    return armlab.__version__


def _write(path: Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text() != text:  # unchanged pages keep their time: no rebuild
        path.write_text(text)


def modules(package: str) -> list[str]:
    """The importable modules of ``package`` (its own ``__init__`` first), sorted by name."""
    pkg = importlib.import_module(package)
    names = [info.name for info in pkgutil.iter_modules(pkg.__path__, package + ".") if not info.ispkg]
    return [package, *sorted(names)]


def write_api(folder: Path) -> None:
    """``api/index.md`` (every name of ``armlab.__all__``) and ``api/<module>.md`` per subpackage module."""
    import armlab

    entries = []
    for name in armlab.__all__:
        if name.startswith("__"):
            continue
        value = getattr(armlab, name)
        kind = "autoclass" if isinstance(value, type) else "autofunction"
        entries.append(f".. {kind}:: armlab.{name}\n")
    packages = []
    for package, what in SUBPACKAGES.items():
        items = []
        for module in modules(package):
            page = f"{module}.md"
            _write(folder / "api" / page,
                   f"# `{module}`\n\n```{{eval-rst}}\n.. automodule:: {module}\n   :members:\n```\n")
            items.append(module)
        packages.append(f"## `{package}`: {what}\n\n```{{toctree}}\n:maxdepth: 1\n\n"
                        + "".join(f"{m}\n" for m in items) + "```\n")
    _write(folder / "api" / "index.md",
           "# API reference\n\nThe public Python API is what `import armlab` gives (the CLI is a thin layer over "
           "it). Each name below, then each module of the subpackages.\n\n## `armlab`\n\n"
           + "```{eval-rst}\n" + "\n".join(entries) + "```\n\n" + "\n".join(packages))


def reproduction(folder: Path) -> Path:
    """A fresh fast reproduction of every paper in ``folder/reproduction`` (``ARMLAB_DOCS_REPRODUCTION``: an
    existing one to use instead); its ``report.md``."""
    given = os.environ.get("ARMLAB_DOCS_REPRODUCTION")
    if given:
        return Path(given) / "report.md"
    from armlab.papers.reproduce import reproduce

    out = folder / "reproduction"
    return reproduce(out, fast=True, progress=lambda line: print(f"docs: {line}", flush=True)).report


_ANCHOR = re.compile(r'^(#+ .*?) <a id="([^"]+)"></a>$')
_INLINE_ANCHOR = re.compile(r'<a id="([^"]+)"></a>')


def paper_sections(report: Path) -> dict[str, str]:
    """The report's Markdown cut into its papers' sections (``{"000": text, …}``), as MyST reads it: each
    ``<a id>`` anchor becomes a MyST target, and a link to another paper's anchor a link to that page."""
    sections: dict[str, list[str]] = {}
    current = None
    for line in report.read_text().splitlines():
        m = re.match(r"^## Paper (\d{3}):", line)
        if m:
            current = m[1]
            sections[current] = []
            continue
        if current is None:
            continue
        heading = _ANCHOR.match(line)
        if heading:
            sections[current] += [f"({current}-page-{heading[2]})=", heading[1]]
            continue
        line = _INLINE_ANCHOR.sub("", line)
        line = re.sub(r"\]\(#([^)]+)\)", rf"](#{current}-page-\1)", line)
        line = re.sub(r"\]\((\d{3})/", r"](../reproduction/\1/", line)
        sections[current].append(line)
    return {paper: "\n".join(lines) + "\n" for paper, lines in sections.items()}


def write_papers(folder: Path) -> None:
    """``papers/NNN.md`` per paper: its arm's and method's docstrings, then its section of the report."""
    report = reproduction(folder)
    target = folder / "reproduction"
    if report.parent.resolve() != target.resolve():
        shutil.copytree(report.parent, target, dirs_exist_ok=True)
    sections = paper_sections(target / "report.md")
    for paper, (title, arms, mods) in PAPERS.items():
        docs = "".join(f"```{{eval-rst}}\n.. automodule:: {m}\n   :no-index:\n```\n\n" for m in mods)
        _write(folder / "papers" / f"{paper}.md",
               f"# Paper {paper}: {title}\n\n{paper_lead(paper, arms)}"
               f"## The report: the paper beside armlab\n\nFrom `armlab reproduce --fast` at the build of these "
               f"pages (the full run, `make run`, samples finer).\n\n{sections[paper]}\n"
               f"## Reference: the paper's arm and equations, as armlab writes them\n\n{docs}")


def write_notebooks(folder: Path) -> None:
    """The repository's notebooks copied in (MyST-NB executes them in the build)."""
    out = folder / "notebooks"
    out.mkdir(parents=True, exist_ok=True)
    for notebook in sorted((ROOT / "notebooks").glob("*.ipynb")):
        data = notebook.read_bytes()
        if not (out / notebook.name).exists() or (out / notebook.name).read_bytes() != data:
            (out / notebook.name).write_bytes(data)


#: The width the CLI reference's ``--help`` texts are wrapped to (argparse reads ``COLUMNS``).
HELP_WIDTH = 100


def commands() -> dict[str, tuple[argparse.ArgumentParser, str]]:
    """Every ``armlab`` subcommand by name: its parser and its one-line help, from the CLI's own parser
    (``armlab.cli.build_parser``)."""
    from armlab.cli import build_parser

    (sub,) = [a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction)]  # argparse's way in
    helps = {action.dest: action.help or "" for action in sub._choices_actions}
    return {name: (parser, helps.get(name, "")) for name, parser in sub.choices.items()}


def write_cli(folder: Path) -> None:
    """``cli/index.md`` (every command with its one-line help) and ``cli/<command>.md`` (its ``--help``, wrapped
    to :data:`HELP_WIDTH` columns)."""
    previous = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = str(HELP_WIDTH)
    try:
        shown = commands()
        for name, (parser, what) in shown.items():
            _write(folder / "cli" / f"{name}.md",
                   f"# `armlab {name}`\n\n{what}\n\n```text\n{parser.format_help()}```\n")
    finally:
        if previous is None:
            os.environ.pop("COLUMNS", None)
        else:
            os.environ["COLUMNS"] = previous
    listing = "".join(f"- [`armlab {name}`]({name}.md): {what}\n" for name, (_, what) in shown.items())
    _write(folder / "cli" / "index.md",
           "# CLI reference\n\nEvery command of `armlab`, its options as `armlab COMMAND --help` prints them "
           f"(generated from the parser at the build of these pages).\n\n{listing}\n"
           "```{toctree}\n:hidden:\n\n" + "".join(f"{name}\n" for name in shown) + "```\n")


def write_all(folder: Path) -> None:
    """Every generated page, into ``folder``."""
    write_cli(folder)
    write_api(folder)
    write_notebooks(folder)
    write_papers(folder)
