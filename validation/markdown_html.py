"""A minimal Markdown-to-HTML renderer for the report's own subset.

The report writes headings, paragraphs, bullet lists, pipe tables, images, inline code and
bold; this renders exactly that, so the report needs no extra dependency.
"""

from __future__ import annotations

import html
import re

_INLINE = [
    (re.compile(r"!\[([^\]]*)\]\(([^)]+)\)"), r'<img alt="\1" src="\2" loading="lazy">'),
    (re.compile(r"\*\*([^*]+)\*\*"), r"<strong>\1</strong>"),
    (re.compile(r"`([^`]+)`"), r"<code>\1</code>"),
]

_STYLE = """body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;}
table{border-collapse:collapse;margin:1em 0;font-size:0.9em}
td,th{border:1px solid #bbb;padding:3px 6px;text-align:left}
th{background:#eee} img{max-width:48%;margin:4px;border:1px solid #ddd}
code{background:#f4f4f4;padding:0 3px}"""


def _inline(text: str) -> str:
    out = html.escape(text, quote=False)
    for pattern, repl in _INLINE:
        out = pattern.sub(repl, out)
    return out


def _cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def to_html(markdown: str, title: str = "report") -> str:
    """Render the report's Markdown subset as a standalone HTML page."""
    lines = markdown.splitlines()
    body: list[str] = []
    i = 0
    while i < len(lines):
        line = lines[i]
        if not line.strip():
            i += 1
            continue
        m = re.match(r"^(#{1,6})\s+(.*)$", line)
        if m:
            n = len(m.group(1))
            body.append(f"<h{n}>{_inline(m.group(2))}</h{n}>")
            i += 1
        elif line.lstrip().startswith("|"):
            rows = []
            while i < len(lines) and lines[i].lstrip().startswith("|"):
                rows.append(lines[i])
                i += 1
            head, rest = rows[0], [r for r in rows[1:] if not re.match(r"^\s*\|[\s:|-]+\|\s*$", r)]
            body.append("<table><tr>" + "".join(f"<th>{_inline(c)}</th>" for c in _cells(head))
                        + "</tr>")
            for r in rest:
                body.append("<tr>" + "".join(f"<td>{_inline(c)}</td>" for c in _cells(r))
                            + "</tr>")
            body.append("</table>")
        elif line.lstrip().startswith("- "):
            body.append("<ul>")
            while i < len(lines) and lines[i].lstrip().startswith("- "):
                body.append(f"<li>{_inline(lines[i].lstrip()[2:])}</li>")
                i += 1
            body.append("</ul>")
        else:
            para = []
            while i < len(lines) and lines[i].strip() and not re.match(r"^(#|\||- )",
                                                                        lines[i].lstrip()):
                para.append(lines[i].strip())
                i += 1
            body.append(f"<p>{_inline(' '.join(para))}</p>")
    return (f"<!DOCTYPE html>\n<html><head><meta charset='utf-8'><title>{html.escape(title)}"
            f"</title><style>{_STYLE}</style></head><body>\n" + "\n".join(body)
            + "\n</body></html>\n")
