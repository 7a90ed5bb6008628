"""A tiny document model rendered both as Markdown and as a self-contained HTML page."""
from __future__ import annotations

import base64
import html
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

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
tr.consistent td.verdict { color: #126b2a; font-weight: bold; }
tr.faster td.verdict, tr.slower td.verdict { color: #a15c00; font-weight: bold; }
.figures { display: flex; flex-wrap: wrap; gap: 1em; align-items: flex-start; }
figure { flex: 1 1 45%; min-width: 320px; max-width: 49%; margin: .5em 0; }
figure img { width: 100%; border: 1px solid #eee; }
.figures.wide figure { flex-basis: 100%; max-width: 100%; }
figcaption { font-size: .85em; color: #555; }
code { background: #f4f4f4; padding: 0 .2em; }
.meta { color: #555; font-size: .9em; }
"""


@dataclass
class Document:
    title: str
    blocks: list = field(default_factory=list)

    def heading(self, text: str, level: int = 2):
        self.blocks.append(("heading", level, text))

    def paragraph(self, text: str, css: str = ""):
        self.blocks.append(("paragraph", text, css))

    def table(self, frame: pd.DataFrame, verdict_column: str | None = None):
        self.blocks.append(("table", frame, verdict_column))

    def figures(self, items: list[tuple[Path, str]], wide: bool = False):
        """(PNG path, caption) pairs shown side by side; ``wide``: each the full page width."""
        self.blocks.append(("figures", items, wide))

    # -- rendering ------------------------------------------------------------------------
    def markdown(self, relative_to: Path) -> str:
        out = [f"# {self.title}", ""]
        for block in self.blocks:
            kind = block[0]
            if kind == "heading":
                out += ["#" * block[1] + " " + block[2], ""]
            elif kind == "paragraph":
                out += [block[1], ""]
            elif kind == "table":
                # a literal | (as in h |log h|^1/4) would split a cell: GFM wants it escaped
                frame = block[1].astype(str).map(lambda cell: cell.replace("|", "\\|"))
                header = [str(c).replace("|", "\\|") for c in frame.columns]
                out.append("| " + " | ".join(header) + " |")
                out.append("|" + "|".join("---" for _ in header) + "|")
                out += ["| " + " | ".join(row) + " |" for row in frame.itertuples(index=False)]
                out.append("")
            elif kind == "figures":
                for path, caption in block[1]:
                    rel = Path(path).relative_to(relative_to)
                    out += [f"![{caption}]({rel.as_posix()})", "", f"*{caption}*", ""]
        return "\n".join(out)

    def html(self) -> str:
        parts = [f"<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>{html.escape(self.title)}</title>",
                 f"<style>{CSS}</style></head><body>", f"<h1>{html.escape(self.title)}</h1>"]
        for block in self.blocks:
            kind = block[0]
            if kind == "heading":
                parts.append(f"<h{block[1]}>{html.escape(block[2])}</h{block[1]}>")
            elif kind == "paragraph":
                css = f" class='{block[2]}'" if block[2] else ""
                parts.append(f"<p{css}>{_inline(block[1])}</p>")
            elif kind == "table":
                frame, verdict = block[1], block[2]
                rows = ["<table><thead><tr>" + "".join(f"<th>{html.escape(str(c))}</th>" for c in frame.columns) + "</tr></thead><tbody>"]
                for record in frame.to_dict("records"):
                    css = f" class='{html.escape(str(record[verdict]).split()[0])}'" if verdict and str(record[verdict]) else ""
                    cells = "".join(
                        f"<td{' class=verdict' if c == verdict else ''}>{html.escape(str(v))}</td>" for c, v in record.items())
                    rows.append(f"<tr{css}>{cells}</tr>")
                rows.append("</tbody></table>")
                parts.append("".join(rows))
            elif kind == "figures":
                parts.append(f"<div class='figures{' wide' if block[2] else ''}'>")
                for path, caption in block[1]:
                    data = base64.b64encode(Path(path).read_bytes()).decode()
                    parts.append(f"<figure><img alt='{html.escape(caption)}' src='data:image/png;base64,{data}'>"
                                 f"<figcaption>{html.escape(caption)}</figcaption></figure>")
                parts.append("</div>")
        parts.append("</body></html>")
        return "\n".join(parts)


def _inline(text: str) -> str:
    """`code` spans in otherwise escaped text."""
    pieces = html.escape(text).split("`")
    return "".join(f"<code>{p}</code>" if k % 2 else p for k, p in enumerate(pieces))
