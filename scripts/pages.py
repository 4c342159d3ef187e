"""What the two pages share (docs/viewer.md): make_viewer.py's viewer.html of a run and
make_report.py's report.html of a study are each one self-contained file, a template from viewer/
with uPlot, the styles, the page's script and its data inlined. Here: finding viewer/ and uPlot,
the page's script with its parts inlined (CORRIDORSIM_INCLUDE), the data as JSON that cannot end
its <script> element, the template (its shared head and tail inlined) filled in one pass, and the
page written atomically with the commands' exit codes (2: a malformed input, 1: the page could not
be made or written)."""

import html
import json
import os
import re
import sys

import system_python  # beside this file (the page scripts put scripts/ on sys.path)

system_python.use_corridorsim_with("files")
from corridorsim import files  # noqa: E402


def viewer_dir():
    """The page's sources: <data>/viewer beside <data>/scripts (the checkout, a build tree's
    links, or share/corridorsim installed)."""
    return os.path.join(os.path.dirname(os.path.realpath(__file__)), "..", "viewer")


def uplot_file(name):
    """uPlot's dist file: viewer/vendor/ when installed, viewer/node_modules/ in a checkout
    (scripts/setup.sh runs npm ci there)."""
    base = viewer_dir()
    for candidate in (os.path.join(base, "vendor", "uplot", name),
                      os.path.join(base, "node_modules", "uplot", "dist", name)):
        if os.path.isfile(candidate):
            return candidate
    raise FileNotFoundError(f"uPlot's {name} is not installed under {base} "
                            "(scripts/setup.sh runs `npm ci` in viewer/)")


def read_asset(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


LONE_SURROGATE = re.compile("[\ud800-\udfff]")


def valid_text(text):
    """`text` as text a UTF-8 file can hold: each lone surrogate (a byte of a file name that is
    not UTF-8, as Python decodes it, or a `\\ud800` escape read from a JSON file) becomes U+FFFD."""
    return LONE_SURROGATE.sub("\ufffd", text)


def page_json(data):
    """`data` as the page's JSON text (valid_text: any string may come from outside)."""
    return valid_text(json.dumps(data, separators=(",", ":"), allow_nan=False,
                                 ensure_ascii=False))


def json_in_script(text):
    """JSON text for <script type="application/json">: every `<`, `>` and `&` written as a JSON
    escape (\\u003c, \\u003e, \\u0026), so that no string (`</script>`, `<!--<script>`) can end
    the element or change how the HTML tokenizer reads the rest of the page. JSON holds these
    characters only inside strings, where the escape stands for the same character."""
    return (valid_text(text).replace("<", "\\u003c").replace(">", "\\u003e")
            .replace("&", "\\u0026"))


def script_safe(text):
    """The page's own JavaScript inside <script>: no `</` can close the element. A source holding
    `<!--` (the HTML tokenizer's escaped script states, where `</script>` no longer ends the
    element) is refused rather than embedded."""
    if "<!--" in text:
        raise RuntimeError("a page source holds '<!--', which would change how the browser reads "
                           "the rest of the page")
    return text.replace("</", "<\\/")


def render_page(template_path, parts):
    """The template (with_parts: its parts inlined) with each placeholder of `parts` (each present
    exactly once) replaced in one pass, so that nothing inserted is searched for placeholders
    again."""
    page = with_parts(template_path)
    for key in parts:
        if page.count(key) != 1:
            raise RuntimeError(f"{template_path}: expected one {key}, found {page.count(key)}")
    out, i = [], 0
    for position, key in sorted((page.index(k), k) for k in parts):
        out.append(page[i:position])
        out.append(parts[key])
        i = position + len(key)
    out.append(page[i:])
    return "".join(out)


# A line of a page source that names a part to inline there: `/*CORRIDORSIM_INCLUDE part.js*/` in
# a script, `<!--CORRIDORSIM_INCLUDE part.html-->` in a template.
INCLUDE = re.compile(r"^[ \t]*(?:/\*|<!--)CORRIDORSIM_INCLUDE ([A-Za-z0-9_.-]+)(?:\*/|-->)\n",
                     re.MULTILINE)


def with_parts(path):
    """The page source at `path` with each INCLUDE line replaced by the part it names (a file of
    the same folder), in place: page.js, the pages' shared helpers, into viewer.js and report.js;
    viewer_*.js, the run viewer's parts, into viewer.js; page_head.html, page_header.html and
    page_tail.html into both templates. A part's opening comment (`/* ... */` or `<!-- ... -->`)
    is for the reader of its file and stays out."""
    base = os.path.dirname(path)

    def part(match):
        text = read_asset(os.path.join(base, match.group(1)))
        for start, end in (("/*", "*/\n"), ("<!--", "-->\n")):
            if text.startswith(start):
                return text[text.index(end) + len(end):]
        return text

    return INCLUDE.sub(part, read_asset(path))


def fill_page(template, script, data_json, title):
    """viewer/<template> with uPlot, viewer.css, the page's script (viewer/<script>, with_parts),
    the data and the title inlined."""
    base = viewer_dir()
    return render_page(os.path.join(base, template), {
        "/*CORRIDORSIM_UPLOT_CSS*/": read_asset(uplot_file("uPlot.min.css")),
        "/*CORRIDORSIM_VIEWER_CSS*/": read_asset(os.path.join(base, "viewer.css")),
        "/*CORRIDORSIM_UPLOT_JS*/": script_safe(read_asset(uplot_file("uPlot.iife.min.js"))),
        "/*CORRIDORSIM_PAGE_JS*/": script_safe(with_parts(os.path.join(base, script))),
        "CORRIDORSIM_DATA_JSON": json_in_script(data_json),
        "CORRIDORSIM_TITLE": html.escape(valid_text(title)),
    })


def keep_path_bytes(stream):
    """A path printed to `stream` keeps the bytes it was given, UTF-8 or not."""
    if hasattr(stream, "reconfigure"):
        stream.reconfigure(errors="surrogateescape")


def write_page(out, page, program):
    """Writes the page atomically (a temporary file beside it, then rename); False, with the
    reason on stderr, when it cannot."""
    tmp = out + ".tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(page)
        os.replace(tmp, out)
    except OSError as e:
        print(f"{program}: cannot write {out}: {e}", file=sys.stderr)
        return False
    return True


def make_page(program, folder, out, build, errors):
    """Runs build() (the page's text) and writes the page to `out`. Returns the exit code: 2 when
    an input file is malformed (files.InputError: path:line: message), 1 when build() raises one
    of `errors` or the page cannot be written (the reason on stderr), 0 when written."""
    try:
        page = build()
    except files.InputError as e:
        print(f"{program}: {e}", file=sys.stderr)
        return 2
    except errors as e:
        print(f"{program}: {folder}: {type(e).__name__}: {e}", file=sys.stderr)
        return 1
    if not write_page(out, page, program):
        return 1
    return 0
