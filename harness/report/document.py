"""A tiny document model rendered both as Markdown and as a self-contained HTML page: headings
(level 2 listed in a table of contents at ``contents()``), paragraphs, tables (a verdict column
colours its rows; ``matrix`` colours each cell), figures, and collapsible parts (``details``).

The HTML page embeds every figure, so that it opens offline; to keep it light the PNGs are
embedded as 256-colour lossless WebP (the figures are line plots and colour maps, which 256
colours draw well, in files much smaller than the PNGs: tests/test_report.py asks for less than
half; the PNGs stay in report/figures at full colour for the Markdown)."""
from __future__ import annotations

import base64
import html
import io
import re
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
from PIL import Image

from ..study.storage.files import write_atomic
from .plots import VERDICT_COLORS

CSS = """
body { font-family: Georgia, 'DejaVu Serif', serif; max-width: 1060px; margin: 2em auto; padding: 0 1em;
       color: #222; line-height: 1.45; }
h1, h2, h3 { font-family: 'Helvetica Neue', Arial, sans-serif; color: #1b3a5c; }
h2 { border-bottom: 1px solid #ccd; padding-bottom: .2em; margin-top: 2em; }
table { border-collapse: collapse; margin: .8em 0; font-size: 0.86em;
        font-family: 'Helvetica Neue', Arial, sans-serif; }
th, td { border: 1px solid #ccd; padding: .25em .55em; text-align: right; }
th { background: #eef1f6; }
td:first-child, th:first-child { text-align: left; }
tr.meets td.verdict { color: #126b2a; font-weight: bold; }
tr.above td.verdict { color: #1b4f8a; font-weight: bold; }
tr.below td.verdict { color: #a11; font-weight: bold; }
tr.pre-asymptotic td.verdict { color: #a15c00; font-weight: bold; }
tr.consistent td.verdict { color: #126b2a; font-weight: bold; }
tr.faster td.verdict, tr.slower td.verdict { color: #a15c00; font-weight: bold; }
.figures { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
figure { flex: 1 1 45%; min-width: 320px; max-width: 49%; margin: .5em 0; }
figure img { width: 100%; border: 1px solid #eee; }
.figures.wide figure { flex-basis: 100%; max-width: 100%; }
figcaption { font-size: .85em; color: #555; }
code { background: #f4f4f4; padding: 0 .2em; }
.meta { color: #555; font-size: .9em; }
nav.contents { background: #f7f8fb; border: 1px solid #dde; padding: .3em 1em; font-size: .92em;
               font-family: 'Helvetica Neue', Arial, sans-serif; }
nav.contents ol { margin: .3em 0; padding-left: 1.4em; }
nav.contents ol ol { columns: 2; font-size: .95em; }
details { margin: .6em 0; border: 1px solid #dde; border-radius: 4px; padding: .2em .8em; }
details > summary { cursor: pointer; font-family: 'Helvetica Neue', Arial, sans-serif; color: #1b3a5c;
                    font-weight: bold; padding: .3em 0; }
details[open] > summary { border-bottom: 1px solid #eef; margin-bottom: .4em; }
summary .counts { font-weight: normal; color: #555; font-size: .9em; margin-left: .6em; }
.scroll { overflow-x: auto; }
table.matrix { font-size: .78em; }
table.matrix td { text-align: center; white-space: nowrap; padding: .2em .4em; }
table.matrix td:first-child { text-align: left; }
""" + "".join(f"table.matrix td.{name.replace(' ', '-')} {{ background: {colour}; }}\n"
              for name, colour in VERDICT_COLORS.items())

# opens a collapsed part when a link of the contents (or the address) points into it
SCRIPT = """
function openTarget() {
  const target = location.hash && document.getElementById(decodeURIComponent(location.hash.slice(1)));
  for (let node = target; node; node = node.parentElement) if (node.tagName === 'DETAILS') node.open = true;
  if (target) target.scrollIntoView();
}
window.addEventListener('hashchange', openTarget);
window.addEventListener('DOMContentLoaded', openTarget);
"""


def anchor(text: str) -> str:
    """The id of a heading: lower case, words joined by hyphens (GitHub's way, near enough)."""
    return re.sub(r"[^\w]+", "-", text.lower()).strip("-")


EMBEDDED = ".embedded"        # beside the figures: their page versions, made as they are drawn


def embedded_path(path: Path) -> Path:
    """Where the page version of the figure ``path`` is kept (``save_compact``)."""
    return Path(path).parent / EMBEDDED / f"{Path(path).stem}.webp"


def _webp(source) -> bytes:
    """A PNG (a path, or its bytes) as 256-colour lossless WebP."""
    with Image.open(io.BytesIO(source) if isinstance(source, bytes) else source) as image:
        buffer = io.BytesIO()
        # the fast octree palette: faster than median cut, and smaller files; the colour maps
        # show a few bands
        image.convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE, dither=Image.Dither.NONE).convert(
            "RGB").save(buffer, "WEBP", lossless=True, method=2)
    return buffer.getvalue()


def save_compact(path: Path, page_png: bytes | None = None) -> None:
    """The page version of the PNG ``path``, made where the figure is drawn (the figure
    processes, side by side: the page then only reads it): from
    ``page_png``, the figure drawn at the page's resolution (``figures.PAGE_DPI``), else from
    the PNG file."""
    target = embedded_path(path)
    target.parent.mkdir(exist_ok=True)
    write_atomic(target, _webp(path if page_png is None else page_png))


def compact_image(path: Path) -> tuple[str, bytes]:
    """(MIME type, bytes) of a figure as the HTML page embeds it: 256-colour lossless WebP, the
    one ``save_compact`` made if it is not older than the PNG."""
    kept = embedded_path(path)
    if kept.is_file() and kept.stat().st_mtime >= Path(path).stat().st_mtime:
        return "image/webp", kept.read_bytes()
    return "image/webp", _webp(path)


@dataclass
class Document:
    title: str
    blocks: list = field(default_factory=list)

    def heading(self, text: str, level: int = 2, key: str | None = None):
        """A heading; ``key``: its anchor (default from the text)."""
        self.blocks.append(("heading", level, text, key or anchor(text)))

    def contents(self):
        """Here: a list of links to every level-2 heading, and under one to the ``details``
        that follow it (each case of the report)."""
        self.blocks.append(("contents",))

    @contextmanager
    def details(self, summary: str, key: str, counts: str = "", open_: bool = False, listed: str | None = None):
        """The blocks added inside, collapsed under one line (``summary``, then ``counts`` in
        grey), with the anchor ``key``; ``listed``: its link text in the contents, under the
        heading before it (None: not listed)."""
        self.blocks.append(("details", summary, key, counts, open_, listed))
        yield self
        self.blocks.append(("end details",))

    def matrix(self, text: pd.DataFrame, classes: pd.DataFrame):
        """A table whose every cell is coloured by its class (a verdict), the index as the first column."""
        self.blocks.append(("matrix", text, classes))

    def paragraph(self, text: str, css: str = ""):
        self.blocks.append(("paragraph", text, css))

    def table(self, frame: pd.DataFrame, verdict_column: str | None = None):
        self.blocks.append(("table", frame, verdict_column))

    def figures(self, items: list[tuple[Path, str]], wide: bool = False):
        """(PNG path, caption) pairs shown side by side; ``wide``: each the full page width."""
        self.blocks.append(("figures", items, wide))

    # -- rendering ------------------------------------------------------------------------
    def outline(self) -> list[tuple[str, str, list[tuple[str, str]]]]:
        """(text, key, [(summary, key) of the details under it]) of every level-2 heading."""
        out = []
        for block in self.blocks:
            if block[0] == "heading" and block[1] == 2:
                out.append((block[2], block[3], []))
            elif block[0] == "details" and block[5] and out:
                out[-1][2].append((block[5], block[2]))
        return out

    def markdown(self, relative_to: Path) -> str:
        out = [f"# {self.title}", ""]
        for block in self.blocks:
            kind = block[0]
            if kind == "heading":
                out += [f'<a id="{block[3]}"></a>', "", "#" * block[1] + " " + block[2], ""]
            elif kind == "contents":
                out += ["**Contents**", ""]
                for text, key, parts in self.outline():
                    out.append(f"1. [{text}](#{key})")
                    out += [f"   - [{summary}](#{part})" for summary, part in parts]
                out.append("")
            elif kind == "paragraph":
                out += [block[1], ""]
            elif kind in ("table", "matrix"):
                frame = block[1].reset_index() if kind == "matrix" else block[1]
                out += _markdown_table(frame)
            elif kind == "figures":
                for path, caption in block[1]:
                    rel = Path(path).relative_to(relative_to)
                    out += [f"![{caption}]({rel.as_posix()})", "", f"*{caption}*", ""]
            elif kind == "details":
                counts = f" ({block[3]})" if block[3] else ""
                out += [f'<details id="{block[2]}"><summary><b>{html.escape(block[1])}</b>{html.escape(counts)}</summary>', ""]
            elif kind == "end details":
                out += ["</details>", ""]
        return "\n".join(out)

    def html(self) -> str:
        parts = [f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>"
                 f"<meta name='viewport' content='width=device-width, initial-scale=1'><title>{html.escape(self.title)}</title>",
                 f"<style>{CSS}</style><script>{SCRIPT}</script></head><body>", f"<h1>{html.escape(self.title)}</h1>"]
        for block in self.blocks:
            kind = block[0]
            if kind == "heading":
                parts.append(f"<h{block[1]} id='{block[3]}'>{html.escape(block[2])}</h{block[1]}>")
            elif kind == "contents":
                items = []
                for text, key, subs in self.outline():
                    inner = "".join(f"<li><a href='#{part}'>{html.escape(summary)}</a></li>" for summary, part in subs)
                    items.append(f"<li><a href='#{key}'>{html.escape(text)}</a>" + (f"<ol>{inner}</ol>" if inner else "") + "</li>")
                parts.append(f"<nav class='contents'><b>Contents</b><ol>{''.join(items)}</ol></nav>")
            elif kind == "paragraph":
                css = f" class='{block[2]}'" if block[2] else ""
                parts.append(f"<p{css}>{_inline(block[1])}</p>")
            elif kind == "table":
                frame, verdict = block[1], block[2]
                rows = ["<div class='scroll'><table><thead><tr>" + "".join(f"<th>{html.escape(str(c))}</th>" for c in frame.columns)
                        + "</tr></thead><tbody>"]
                for record in frame.to_dict("records"):
                    css = f" class='{html.escape(str(record[verdict]).split()[0])}'" if verdict and str(record[verdict]) else ""
                    cells = "".join(
                        f"<td{' class=verdict' if c == verdict else ''}>{html.escape(str(v))}</td>" for c, v in record.items())
                    rows.append(f"<tr{css}>{cells}</tr>")
                rows.append("</tbody></table></div>")
                parts.append("".join(rows))
            elif kind == "matrix":
                text, classes = block[1], block[2]
                head = "".join(f"<th>{html.escape(str(c))}</th>" for c in [text.index.name or ""] + list(text.columns))
                rows = [f"<div class='scroll'><table class='matrix'><thead><tr>{head}</tr></thead><tbody>"]
                for key, row in text.iterrows():
                    cells = "".join(f"<td class='{html.escape(str(classes.loc[key, c]).replace(' ', '-'))}' "
                                    f"title='{html.escape(str(classes.loc[key, c]))}'>{html.escape(str(v))}</td>"
                                    for c, v in row.items())
                    rows.append(f"<tr><td>{html.escape(str(key))}</td>{cells}</tr>")
                rows.append("</tbody></table></div>")
                parts.append("".join(rows))
            elif kind == "figures":
                parts.append(f"<div class='figures{' wide' if block[2] else ''}'>")
                for path, caption in block[1]:
                    mime, data = compact_image(Path(path))
                    parts.append(f"<figure><img alt='{html.escape(caption)}' src='data:{mime};base64,"
                                 f"{base64.b64encode(data).decode()}'><figcaption>{html.escape(caption)}</figcaption></figure>")
                parts.append("</div>")
            elif kind == "details":
                counts = f"<span class='counts'>{html.escape(block[3])}</span>" if block[3] else ""
                parts.append(f"<details id='{block[2]}'{' open' if block[4] else ''}>"
                             f"<summary>{html.escape(block[1])}{counts}</summary>")
            elif kind == "end details":
                parts.append("</details>")
        parts.append("</body></html>")
        return "\n".join(parts)


def _markdown_table(frame: pd.DataFrame) -> list[str]:
    # a literal | (as in h |log h|^1/4) would split a cell: GFM wants it escaped
    frame = frame.astype(str).map(lambda cell: cell.replace("|", "\\|"))
    header = [str(c).replace("|", "\\|") for c in frame.columns]
    return (["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
            + ["| " + " | ".join(row) + " |" for row in frame.itertuples(index=False)] + [""])


def _inline(text: str) -> str:
    """`code` spans in otherwise escaped text."""
    pieces = html.escape(text).split("`")
    return "".join(f"<code>{p}</code>" if k % 2 else p for k, p in enumerate(pieces))
