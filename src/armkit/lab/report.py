"""The lab report: sections of tables and pictures, written as one self-contained HTML file.

Every picture is embedded in ``index.html`` (base64), so the file can be mailed on its
own; the PNG and GIF files stay next to it for reuse. The folder is marked as an armkit
report with a marker file listing what was written, so that a later run replaces exactly
those files and never touches a folder that is not an armkit report (unless forced).
A run writes its report into a staging folder beside the report folder and swaps it in
only once it is complete (:func:`install_report`): an interrupted run leaves the previous
report as it was.
"""

from __future__ import annotations

import base64
import html
import json
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

from armkit._io import atomic_write
from armkit.errors import InputError

__all__ = ["MARKER", "Section", "Table", "check_folder", "install_report", "prepare_folder", "staging_folder",
           "status_label", "write_report"]

MARKER = ".armkit-report"
_MIME = {".png": "image/png", ".gif": "image/gif"}
_COLORS = {"ok": "#1e7b34", "failed": "#b00020", "n/a": "#6b6b75"}


def status_label(status: str, seeds: bool) -> str:
    """The words for a section status: a seed experiment is "reproduced", a user's arm "checked";
    an experiment the arm cannot do is "not applicable"."""
    return {"ok": "reproduced" if seeds else "checked", "failed": "failed", "n/a": "not applicable"}[status]


@dataclass
class Table:
    """A table of already formatted cells; ``groups`` marks rows that start a new group, ``wrap`` lets
    long cells wrap."""

    title: str
    columns: list[str]
    rows: list[list[str]]
    note: str = ""
    groups: set[int] = field(default_factory=set)
    wrap: bool = False


@dataclass
class Section:
    """One experiment of the report.

    ``status`` is ``"ok"``, ``"failed"`` (it raised an error, or missed its target; the
    message is shown as is) or ``"n/a"`` (the arm cannot do this experiment; the first
    note says why). ``images`` are
    ``(file name in the report folder, caption)``. ``own`` marks a check of armkit's own with no
    seed-report counterpart (the collision check): "checked", never "reproduced".
    """

    key: str
    title: str
    intro: str
    status: str = "ok"
    headline: str = ""
    published: str = ""
    tables: list[Table] = field(default_factory=list)
    images: list[tuple[str, str]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    badge: bool = True
    own: bool = False


def check_folder(folder: Path, force: bool) -> None:
    """Raise unless a report may be written to ``folder``; change nothing.

    Raises
    ------
    InputError
        If ``folder`` is a file, or a non-empty folder without the armkit marker and
        ``force`` is false.
    """
    if folder.exists() and not folder.is_dir():
        raise InputError(f"report folder {str(folder)!r} is a file; expected a folder")
    if not (folder / MARKER).is_file() and folder.is_dir() and any(folder.iterdir()) and not force:
        raise InputError(f"folder {str(folder)!r} exists and is not an armkit report (no {MARKER} "
                         f"file); choose another --out or pass --force to write into it")


def prepare_folder(folder: Path, force: bool) -> None:
    """Make ``folder`` ready for a report: remove our earlier report, refuse foreign folders.

    Only the files the marker lists (inside ``folder``) are removed; anything else stays.

    Raises
    ------
    InputError
        As :func:`check_folder`.
    """
    check_folder(folder, force)
    for target in _listed(folder):
        target.unlink()
    (folder / MARKER).unlink(missing_ok=True)
    folder.mkdir(parents=True, exist_ok=True)


def _listed(folder: Path) -> list[Path]:
    """The existing files the marker of ``folder`` lists, only those directly inside ``folder``."""
    marker = folder / MARKER
    if not marker.is_file():
        return []
    targets = [(folder / name).resolve() for name in json.loads(marker.read_text(encoding="utf-8"))
               .get("files", [])]
    return [t for t in targets if t.parent == folder.resolve() and t.is_file()]


def staging_folder(folder: Path) -> Path:
    """A new empty folder beside ``folder`` (same file system) to write the next report into."""
    folder.parent.mkdir(parents=True, exist_ok=True)
    return Path(tempfile.mkdtemp(prefix=f".{folder.name}.new-", dir=folder.parent))


def install_report(staging: Path, folder: Path, force: bool) -> None:
    """Swap the complete report in ``staging`` in for the one in ``folder``; remove ``staging``.

    The new files are moved in, each with one rename (replacing a file of the same name at
    once), then the earlier report's other files are removed and the marker comes last; so
    until the run is complete the old report stays whole, and other files are never touched.
    """
    check_folder(folder, force)
    folder.mkdir(parents=True, exist_ok=True)
    old = _listed(folder)
    new = sorted(staging.iterdir(), key=lambda p: p.name == MARKER)
    for path in new[:-1]:
        os.replace(path, folder / path.name)
    names = {path.name for path in new}
    for target in old:
        if target.name not in names:
            target.unlink()
    os.replace(new[-1], folder / new[-1].name)
    staging.rmdir()


def _cell(text: str) -> str:
    return html.escape(str(text))


def _table_html(table: Table) -> str:
    """The table as HTML; a column empty in every row (a published value a user's arm lacks) is left out."""
    shown = [j for j in range(len(table.columns))
             if not table.rows or any(row[j] != "" for row in table.rows)]
    head = "".join(f"<th>{_cell(table.columns[j])}</th>" for j in shown)
    body = []
    for k, row in enumerate(table.rows):
        css = ' class="group"' if k in table.groups else ""
        body.append(f"<tr{css}>" + "".join(f"<td>{_cell(row[j])}</td>" for j in shown) + "</tr>")
    note = f'<p class="note">{_cell(table.note)}</p>' if table.note else ""
    css = "table wrap" if table.wrap else ("table wide" if len(shown) > 6 else "table")
    return (f'<div class="{css}"><h4>{_cell(table.title)}</h4><div class="scroll"><table><thead>'
            f'<tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table></div>{note}</div>')


def _image_html(folder: Path, name: str, caption: str) -> str:
    path = folder / name
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return (f'<figure><img alt="{_cell(caption)}" src="data:{_MIME[path.suffix]};base64,{data}">'
            f"<figcaption>{_cell(caption)}</figcaption></figure>")


def _section_html(folder: Path, section: Section, seeds: bool) -> str:
    label, color = status_label(section.status, seeds and not section.own), _COLORS[section.status]
    badge = f' <span class="badge" style="background:{color}">{label}</span>' if section.badge else ""
    parts = [f'<section id="{section.key}"><h2>{_cell(section.title)}{badge}</h2>',
             "".join(f"<p>{_cell(p)}</p>" for p in section.intro.split("\n\n") if p)]
    parts += [f'<p class="note">{_cell(n)}</p>' for n in section.notes]
    parts += [_table_html(t) for t in section.tables]
    if section.images:
        parts.append('<div class="figures">' + "".join(
            _image_html(folder, name, caption) for name, caption in section.images) + "</div>")
    parts.append("</section>")
    return "\n".join(parts)


_CSS = """
body{font-family:-apple-system,Segoe UI,Helvetica,Arial,sans-serif;margin:0 auto;max-width:1180px;
padding:0 24px 60px;color:#222;line-height:1.45}
h1{margin:28px 0 4px}h2{border-bottom:2px solid #e4e4ea;padding-bottom:4px;margin-top:42px}
h4{margin:18px 0 6px}.badge{font-size:12px;color:#fff;border-radius:10px;padding:2px 9px;
vertical-align:middle}.sub{color:#666;margin-top:0}.scroll{overflow-x:auto}
table{border-collapse:collapse;font-size:13px;font-variant-numeric:tabular-nums}
th,td{border:1px solid #dcdce3;padding:3px 8px;text-align:right;white-space:nowrap}
th{background:#f2f2f6}td:first-child,th:first-child{text-align:left}tr.group td{border-top:2px solid #999}
th{white-space:normal;vertical-align:bottom}.wide table{font-size:12px}.wide td,.wide th{padding:2px 5px}
.wide td{white-space:normal}tbody tr:nth-child(even){background:#fafafc}.note{color:#555;font-size:13px}
.figures{display:flex;flex-wrap:wrap;gap:18px;align-items:flex-start}
figure{margin:10px 0}figure img{max-width:100%;border:1px solid #e4e4ea;border-radius:4px}
.wrap td,.wrap th{white-space:normal;text-align:left}.wrap td:nth-child(2){white-space:nowrap}
figcaption{font-size:12px;color:#555;max-width:560px}nav a{margin-right:14px;font-size:14px}
"""


def write_report(folder: Path, title: str, subtitle: str, summary: Table, sections: list[Section],
                 files: list[str], seeds: bool = True, generator: str = "armkit lab") -> Path:
    """Write ``index.html`` (everything embedded) and the marker listing ``files``; return the page.

    ``seeds``: the sections reproduce the seed reports (badge "reproduced") rather than check a
    user's arm (badge "checked"). ``generator``: the command the marker names as the page's author.
    """
    nav = "".join(f'<a href="#{s.key}">{_cell(s.title)}</a>' for s in sections)
    page = (f"<!DOCTYPE html><html lang=\"en\"><head><meta charset=\"utf-8\"><title>{_cell(title)}</title>"
            f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
            f"<style>{_CSS}</style></head><body><h1>{_cell(title)}</h1><p class=\"sub\">{_cell(subtitle)}"
            f"</p><nav>{nav}</nav>{_table_html(summary)}"
            + "".join(_section_html(folder, s, seeds) for s in sections) + "</body></html>\n")
    index = folder / "index.html"
    manifest = {"generator": generator, "files": sorted({*files, "index.html"})}
    for path, text in ((index, page), (folder / MARKER, json.dumps(manifest, indent=1) + "\n")):
        with atomic_write(path) as partial:
            partial.write_text(text, encoding="utf-8")
    return index

