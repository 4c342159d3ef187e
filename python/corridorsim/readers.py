"""The strict reading under every reader of corridorsim.files: InputError (the file, the line and
what is wrong), whole text files with a size bound, JSON with each value's line (JsonReader) and
no NaN or Infinity, CSV tables with a bounded row count and their cells checked by column
(CsvCells), and FolderReader (a folder's files read when first asked for and kept). corridorsim.files
re-exports every name."""

import bisect
import csv
import io
import json
import json.decoder
import json.scanner
import math
import os
import re

# Bounds on what an input may hold.
MAX_CSV_ROWS = 2_000_000
MAX_TEXT_CHARS = 64        # labels, roles and camera names
MAX_FILE_BYTES = 1 << 30   # any text file read whole


class InputError(Exception):
    """A missing or malformed input: file, line (None when unknown) and what is wrong."""

    def __init__(self, path, line, message):
        super().__init__(message)
        self.path, self.line, self.message = path, line, message

    def __str__(self):
        where = self.path if self.line is None else f"{self.path}:{self.line}"
        return f"{where}: {self.message}"


# ------------------------------------------------------------------------------------------------
# Common parts

def read_text(path, max_bytes=None):
    """The text of a regular UTF-8 file of at most `max_bytes` (MAX_FILE_BYTES by default)."""
    if not os.path.isfile(path):
        raise InputError(path, None, "missing")
    limit = MAX_FILE_BYTES if max_bytes is None else max_bytes
    try:
        if os.path.getsize(path) > limit:
            raise InputError(path, None, f"larger than {limit} bytes")
        with open(path, encoding="utf-8") as f:
            return f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(path, None, f"cannot be read: {e}") from None


def data_lines(path):
    """(line number, whitespace-separated fields) of each line of a text file (read_text) that is
    neither empty nor a '#' comment: TUM trajectories and frame lists."""
    for number, line in enumerate(read_text(path).splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        yield number, line.split()


class JsonObject(dict):
    """A JSON object that remembers the line of its opening brace."""
    line = None


class JsonArray(list):
    """A JSON array that remembers the line of its opening bracket."""
    line = None


def no_json_constant(name):
    """json's parse_constant: NaN and Infinity are not JSON (the project writes null)."""
    raise ValueError(f"{name} is not JSON")


def finite_float(text):
    """json's parse_float: a number that overflows a double (1e999) is refused, not infinity."""
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(f"{text[:40]} is not a finite number")
    return value


def load_json(path, top="object", max_bytes=None):
    """Parses a JSON file into JsonObject/JsonArray values that know their line numbers; the top
    level must be a JSON `top` ('object' or 'array')."""
    text = read_text(path, max_bytes)
    newlines = [m.start() for m in re.finditer("\n", text)]

    def line_of(pos):
        return bisect.bisect_left(newlines, pos) + 1

    def parse_object(s_and_end, *args):
        value, end = json.decoder.JSONObject(s_and_end, *args)
        out = JsonObject(value)
        out.line = line_of(s_and_end[1] - 1)
        return out, end

    def parse_array(s_and_end, scan_once):
        value, end = json.decoder.JSONArray(s_and_end, scan_once)
        out = JsonArray(value)
        out.line = line_of(s_and_end[1] - 1)
        return out, end

    # The pure-Python scanner lets us hook object and array parsing (the C one does not).
    decoder = json.JSONDecoder(parse_float=finite_float, parse_constant=no_json_constant)
    decoder.parse_object = parse_object
    decoder.parse_array = parse_array
    decoder.scan_once = json.scanner.py_make_scanner(decoder)
    try:
        root = decoder.decode(text)
    except json.JSONDecodeError as e:
        raise InputError(path, e.lineno, f"column {e.colno}: invalid JSON: {e.msg}") from None
    except RecursionError:
        raise InputError(path, None, "invalid JSON: nested too deeply") from None
    except ValueError as e:  # a non-finite number, or an integer of thousands of digits
        raise InputError(path, None, f"invalid JSON: {e}") from None
    if not isinstance(root, dict if top == "object" else list):
        raise InputError(path, 1, f"the top level is not a JSON {top}")
    return root


class JsonReader:
    """Typed access to optional keys of one JSON file; errors name the file, line and key."""

    def __init__(self, path):
        self.path = path

    def fail(self, parent, where, message):
        raise InputError(self.path, getattr(parent, "line", None), f"{where}: {message}")

    def get(self, obj, key, kind, where):
        """obj[key] if it is of `kind` ('object', 'array', 'number', 'bool', 'text'); None when
        absent or null."""
        value = obj.get(key)
        if value is None:
            return None
        name = f"{where}.{key}" if where else key
        ok = {
            "object": isinstance(value, dict),
            "array": isinstance(value, list),
            "number": isinstance(value, (int, float)) and not isinstance(value, bool),
            "bool": isinstance(value, bool),
            "text": isinstance(value, (str, int)) and not isinstance(value, bool),
        }[kind]
        if not ok:
            self.fail(obj, name, f"expected {kind}, got {json.dumps(value)[:40]}")
        return value

    def integer(self, obj, key, where, minimum=None):
        """obj[key], which must be an integer (at least `minimum` where one is given)."""
        value = obj.get(key)
        if not is_integer(value) or (minimum is not None and value < minimum):
            wanted = ("an integer" if minimum is None else "a non-negative integer"
                      if minimum == 0 else f"an integer of at least {minimum}")
            self.fail(obj, f"{where}.{key}", f"expected {wanted}, got {json.dumps(value)[:40]}")
        return value

    def vec2(self, obj, key, where):
        """The x, y of a [x, y] or [x, y, z] array; None when absent."""
        value = obj.get(key)
        if value is None:
            return None
        ok = (isinstance(value, list) and len(value) in (2, 3) and
              all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value))
        if not ok:
            self.fail(obj, f"{where}.{key}", f"expected [x, y] or [x, y, z] in metres, "
                      f"got {json.dumps(value)[:40]}")
        return float(value[0]), float(value[1])

    def items(self, obj, key):
        """The objects in the array obj[key], each with its name `key[i]`; [] when absent."""
        array = self.get(obj, key, "array", "")
        out = []
        for i, item in enumerate(array or []):
            if not isinstance(item, dict):
                self.fail(array, f"{key}[{i}]", "expected an object")
            out.append((f"{key}[{i}]", item))
        return out


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def is_integer(value):
    return isinstance(value, int) and not isinstance(value, bool)


def read_short_text(r, obj, key, where, required):
    value = r.get(obj, key, "text", where)
    if value is None:
        if required:
            r.fail(obj, f"{where}.{key}", "missing")
        return ""
    value = str(value)
    if len(value) > MAX_TEXT_CHARS:
        r.fail(obj, f"{where}.{key}", f"longer than {MAX_TEXT_CHARS} characters")
    return value


def read_csv_records(path, max_rows=MAX_CSV_ROWS, check_header=None):
    """(header, [(line, [cell])]) of a CSV file: the header's names stripped, then every record as
    long as the header, cells as written; blank rows skipped; quoted cells may hold commas and
    newlines; at most `max_rows` records. `check_header(header)` runs before any record is read."""
    text = read_text(path)
    reader = csv.reader(io.StringIO(text, newline=""))
    try:
        header = [h.strip() for h in next(reader)]
    except StopIteration:
        header = []
    except csv.Error as e:
        raise InputError(path, 1, f"not CSV: {e}") from None
    if not any(header):
        raise InputError(path, 1, "missing the header line")
    if check_header is not None:
        check_header(header)
    rows = []
    line = reader.line_num + 1  # where the next record starts
    try:
        for row in reader:
            start, line = line, reader.line_num + 1
            if not row or all(not cell.strip() for cell in row):
                continue
            if len(row) != len(header):
                raise InputError(path, start, f"expected {len(header)} fields, got {len(row)}")
            if len(rows) == max_rows:
                raise InputError(path, start, f"more than {max_rows} rows")
            rows.append((start, row))
    except csv.Error as e:
        raise InputError(path, line, f"not CSV: {e}") from None
    return header, rows


def read_csv_table(path, columns):
    """The rows of a CSV file whose header holds every name in `columns` (in any order; other
    columns are ignored) as (line, {column: stripped cell}); quoted cells may hold commas and
    newlines. Blank rows are skipped; at most MAX_CSV_ROWS rows."""
    def check_header(header):
        for column in columns:
            if column not in header:
                raise InputError(path, 1, f"the header has no column '{column}'")

    header, records = read_csv_records(path, check_header=check_header)
    index = {c: header.index(c) for c in columns}
    return [(line, {c: row[index[c]].strip() for c in columns}) for line, row in records]


class FolderReader:
    """Base of corridorsim.Run, Study and Dataset: a folder's path (InputError when it is not a
    directory) and the files read from it, each read when first asked for and kept."""

    def __init__(self, path):
        path = os.fspath(path)
        if not os.path.isdir(path):
            raise InputError(path, None, "is not a directory")
        self.path = path
        self._cache = {}

    def __repr__(self):
        return f"{type(self).__name__}({self.path!r})"

    def _cached(self, key, make):
        if key not in self._cache:
            self._cache[key] = make()
        return self._cache[key]


class CsvCells:
    """Typed cells of one CSV row; errors name the file, line and column."""

    def __init__(self, path, line, cells):
        self.path, self.line, self.cells = path, line, cells

    def fail(self, column, message):
        raise InputError(self.path, self.line, f"{column}: {message}")

    def number(self, column, required=True, lo=-math.inf, hi=math.inf):
        """A finite number in [lo, hi]; NaN for an empty cell when not required."""
        cell = self.cells[column]
        if not cell:
            if required:
                self.fail(column, "missing")
            return math.nan
        try:
            value = float(cell)
        except ValueError:
            self.fail(column, f"not a number: '{cell[:40]}'")
        if not math.isfinite(value):
            self.fail(column, f"not finite: '{cell[:40]}'")
        if not lo <= value <= hi:
            self.fail(column, f"{cell[:40]} is outside [{lo:g}, {hi:g}]")
        return value

    def integer(self, column, lo, hi):
        cell = self.cells[column]
        if not re.fullmatch(r"-?[0-9]{1,12}", cell):
            self.fail(column, f"expected an integer, got '{cell[:40]}'")
        value = int(cell)
        if not lo <= value <= hi:
            self.fail(column, f"{value} is outside [{lo}, {hi}]")
        return value

    def choice(self, column, allowed):
        cell = self.cells[column]
        if cell not in allowed:
            shown = [a if a else "(empty)" for a in allowed]
            self.fail(column, f"expected one of {shown}, got '{cell[:40]}'")
        return cell

    def text(self, column, required):
        cell = self.cells[column]
        if required and not cell:
            self.fail(column, "missing")
        if len(cell) > MAX_TEXT_CHARS:
            self.fail(column, f"longer than {MAX_TEXT_CHARS} characters")
        return cell
