"""MkDocs hooks of the brushbem site: pages drawn from the README's sections and from the studies.

A page line ``{{ readme: ## Heading }}`` is replaced by that README section
(up to the next heading of the same or a higher level), so the README and the
site say the same thing from one source; ``{{ gallery }}`` becomes one
section per study figure found in ``docs/figures/<study>/``, with the numbers
the thesis states for that study and the command that recomputes them.  A
block ``{{ rows: STUDY`` / one quantity per line / ``}}`` becomes the table of
those rows of ``docs/thesis-comparison.md`` (thesis, ours, standard error,
deviation, verdict), and ``{{ rows: STUDY rest }}`` the study's rows no earlier
block on the page took: the gallery shows the comparison's numbers as they
are regenerated, never a copy.

The site works from disk and offline (``mkdocs.yml``): ``on_files`` adds
MathJax's single-file SVG build with every TeX extension and its licence from the docs extra's
``django-static-mathjax`` package (MathJax 3, Apache-2.0) under
``assets/mathjax/``, and the Pygments stylesheet of the highlighted code as
``assets/pygments.css``.
"""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _readme_section(heading: str) -> str:
    """The README's section under ``heading`` (without it), to the next heading of its level or higher."""
    lines = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    level = len(heading) - len(heading.lstrip("#"))
    start = lines.index(heading) + 1
    fenced = False
    for index in range(start, len(lines)):
        line = lines[index]
        if line.startswith("```"):
            fenced = not fenced  # a TOML comment in a code block is not a heading
        match = None if fenced else re.match(r"(#{1,6}) ", line)
        if match and len(match.group(1)) <= level:
            return "\n".join(lines[start:index])
    return "\n".join(lines[start:])


def _gallery() -> str:
    from brushbem.studies import STUDIES

    lines = []
    for name, study in STUDIES.items():
        # The thesis's studies draw into docs/figures from docs/reproduction; the studies beyond the
        # thesis into docs/beyond/figures from docs/beyond.
        for tables, figures in (("docs/reproduction", ROOT / "docs" / "figures"),
                                ("docs/beyond", ROOT / "docs" / "beyond" / "figures")):
            folder = figures / name
            images = sorted(folder.glob("*.png")) if folder.is_dir() else []
            if images:
                break
        if not images:
            continue
        lines.append(f"## {name}\n\n{study.title}\n")
        lines.append(f"Recompute: `brushbem study {name} --out out/{name}` (add `--quick` for the coarse grids); "
                     f"the tables behind these figures are in `{tables}/{name}/`.\n")
        if study.numbers:
            lines.append("| quantity | where | thesis |\n| --- | --- | --- |")
            lines += [f"| {n.quantity} | {n.where} | {n.thesis:g} |" for n in study.numbers]
            lines.append("")
        for image in images:
            relative = image.relative_to(ROOT / "docs").as_posix()
            lines.append(f"### {image.stem}\n\n![{image.stem}](../{relative})\n")
    lines.append('<script>window.addEventListener("load", () => document.querySelectorAll("img").forEach('
                 'img => img.setAttribute("data-loaded", String(img.complete && img.naturalWidth > 0))));</script>')
    return "\n".join(lines)


COMPARISON = ROOT / "docs" / "thesis-comparison.md"
ROW_HEADER = "| quantity | where | thesis | ours | standard error | deviation | verdict |\n| --- | --- | --- | --- | --- | --- | --- |"


def comparison_rows() -> dict[str, list[list[str]]]:
    """Per study, the cells of every row of the comparison's verdict tables (without 'explained in')."""
    rows: dict[str, list[list[str]]] = {}
    study = None
    for line in COMPARISON.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            match = re.match(r"^## `(\w+)`", line)
            study = match.group(1) if match else None
            continue
        if study and line.startswith("| ") and not line.startswith(("| quantity", "| ---")):
            cells = [cell.strip() for cell in re.split(r"(?<!\\)\|", line.strip()[1:-1])]  # "\|" is a pipe in a cell
            if len(cells) == 8:
                verdict = re.match(r"\*\*[^*]+\*\*", cells[6])  # the verdict; its evidence stays in the comparison
                rows.setdefault(study, []).append([*cells[:6], verdict.group(0) if verdict else cells[6]])
    return rows


def render_rows(markdown: str) -> str:
    """Every ``{{ rows: ... }}`` block of ``markdown`` replaced by its table (module docstring)."""
    rows = comparison_rows()
    taken: dict[str, set[str]] = {}

    def table(match: re.Match) -> str:
        study, rest = match.group(1), match.group(2).strip()
        by_quantity = {cells[0]: cells for cells in rows.get(study, [])}
        if rest == "rest":
            wanted = [q for q in by_quantity if q not in taken.get(study, set())]
        else:
            wanted = [line.strip() for line in rest.splitlines() if line.strip()]
            unknown = [q for q in wanted if q not in by_quantity]
            if unknown:
                raise ValueError(f"docs/thesis-comparison.md has no row {unknown} in study {study!r}")
        taken.setdefault(study, set()).update(wanted)
        if not wanted:
            return "(none)"
        return ROW_HEADER + "\n" + "\n".join("| " + " | ".join(by_quantity[q]) + " |" for q in wanted)

    return re.sub(r"^\{\{ rows: (\w+)((?: rest )|(?:\n(?:(?!\}\}).*\n)*?))\}\}$", table, markdown, flags=re.MULTILINE)


def on_files(files, config):
    """The site's local assets: MathJax (SVG output: no web fonts to load) and the code's stylesheet."""
    from mkdocs.structure.files import File
    from pygments.formatters import HtmlFormatter

    try:
        import mathjax  # the django-static-mathjax package of the docs extra
    except ImportError as error:
        raise RuntimeError("the documentation needs the docs extra: pip install -e '.[docs]' "
                           "(django-static-mathjax provides the site's MathJax)") from error
    static = Path(mathjax.__file__).resolve().parent / "static" / "mathjax"
    files.append(File.generated(config, "assets/mathjax/tex-svg-full.js", abs_src_path=str(static / "es5" / "tex-svg-full.js")))
    files.append(File.generated(config, "assets/mathjax/LICENSE", abs_src_path=str(static / "LICENSE")))
    files.append(File.generated(config, "assets/pygments.css",
                                content=HtmlFormatter(style="default").get_style_defs(".highlight")))
    return files


def on_page_markdown(markdown: str, page, config, files) -> str:
    if "{{ rows: " in markdown:
        markdown = render_rows(markdown)
    markdown = re.sub(r"^\{\{ readme: (#+ .+?) \}\}$", lambda m: _readme_section(m.group(1)), markdown, flags=re.MULTILINE)
    if "{{ gallery }}" in markdown:
        markdown = markdown.replace("{{ gallery }}", _gallery())
    return markdown
