"""Query a shader's parameters and metadata from Python, as OSL's oslquery
module does: OSLQuery(name) -> shadertype(), shadername(), metadata, and a
sequence of Parameter objects (name, type, isoutput, value, metadata, ...).

osl-mlir reads shaders from their source, so the name is a shader's source
(NAME.osl, or NAME found on the search path) rather than compiled bytecode.
The interface comes from `osl-run --info-json`; osl-run is looked for in the
environment variable OSLMLIR_OSL_RUN, then beside this module
(../bin/osl-run, as the build and an install lay them out), then on PATH.
"""

import json
import os
import shutil
import subprocess

__all__ = ["OSLQuery", "Parameter", "TypeDesc"]

_FLOAT_BASES = ("float", "point", "vector", "normal", "color", "matrix")


def _osl_run():
    found = os.environ.get("OSLMLIR_OSL_RUN")
    if found:
        return found
    here = os.path.dirname(os.path.abspath(__file__))
    beside = os.path.join(os.path.dirname(here), "bin", "osl-run")
    if os.access(beside, os.X_OK):
        return beside
    return shutil.which("osl-run")


def _find_source(shadername, searchpath):
    """NAME.osl or NAME in the first folder of the search path (':' or ';'
    separated) that has it; else the name as given (osl-run then looks for
    it in the current folder)."""
    folders = [f for f in searchpath.replace(";", ":").split(":") if f]
    for folder in folders:
        for candidate in (shadername + ".osl", shadername):
            path = os.path.join(folder, candidate)
            if os.path.isfile(path):
                return path
    return shadername


class TypeDesc:
    """A parameter's type as OSL writes it ("color", "float[3]", "float[]");
    it prints as that text and compares equal to it."""

    def __init__(self, text):
        self._text = text
        base, _, rest = text.partition("[")
        self.basetype = base
        self.arraylen = -1 if not rest else (int(rest[:-1]) if rest[:-1] else 0)

    @property
    def is_array(self):
        return self.arraylen >= 0

    def elementtype(self):
        return TypeDesc(self.basetype)

    def __str__(self):
        return self._text

    def __repr__(self):
        return "TypeDesc(%r)" % self._text

    def __eq__(self, other):
        return str(self) == str(other)

    def __ne__(self, other):
        return not self == other

    def __hash__(self):
        return hash(self._text)


class Parameter:
    """One shader parameter or metadatum."""

    def __init__(self, entry):
        self.name = entry["name"]
        self.type = TypeDesc(entry["type"])
        self.isoutput = entry["isoutput"]
        self.isclosure = entry["isclosure"]
        self.isstruct = entry["isstruct"]
        self.varlenarray = entry["varlenarray"]
        self.validdefault = entry["validdefault"]
        self.structname = entry.get("structname", "")
        self.fields = tuple(entry.get("fields", ()))
        self.spacename = entry.get("spacename", "")
        self.metadata = tuple(Parameter(m) for m in entry["metadata"])
        self.value = self._value(entry.get("value"))

    def _value(self, values):
        # A closure or struct has no value; one number or string is itself;
        # triples, matrices and arrays are tuples of their numbers.
        if values is None:
            return None
        base = self.type.basetype
        if base in _FLOAT_BASES:
            values = [float(v) for v in values]
        if len(values) == 1 and not self.type.is_array:
            return values[0]
        return tuple(values)

    def __repr__(self):
        return "<Parameter %s %s>" % (self.type, self.name)


class OSLQuery:
    """The interface of one shader: OSLQuery("name", searchpath="")."""

    def __init__(self, shadername="", searchpath=""):
        self._error = ""
        self._clear()
        if shadername:
            self.open(shadername, searchpath)

    def _clear(self):
        self._type, self._name, self._params, self.metadata = "", "", [], ()

    def open(self, shadername, searchpath=""):
        """Reads the shader's interface; False (see geterror()) if it cannot."""
        self._clear()
        tool = _osl_run()
        if not tool:
            self._error = "osl-run not found (set OSLMLIR_OSL_RUN)"
            return False
        run = subprocess.run([tool, "--info-json", _find_source(shadername, searchpath)],
                             capture_output=True, text=True)
        if run.returncode != 0:
            self._error = run.stderr.strip() or "cannot read shader \"%s\"" % shadername
            return False
        query = json.loads(run.stdout)
        self._type, self._name = query["shadertype"], query["shadername"]
        self._params = [Parameter(p) for p in query["params"]]
        self.metadata = tuple(Parameter(m) for m in query["metadata"])
        return True

    def shadertype(self):
        return self._type

    def shadername(self):
        return self._name

    def nparams(self):
        return len(self._params)

    def getparam(self, key):
        """The parameter at an index or with a name; None if there is none."""
        if isinstance(key, int):
            return self._params[key] if 0 <= key < len(self._params) else None
        return next((p for p in self._params if p.name == key), None)

    def parameters(self):
        return tuple(self._params)

    def geterror(self, clear=True):
        error = self._error
        if clear:
            self._error = ""
        return error

    def __len__(self):
        return len(self._params)

    def __getitem__(self, key):
        p = self.getparam(key)
        if p is None:
            raise IndexError(key) if isinstance(key, int) else KeyError(key)
        return p

    def __iter__(self):
        return iter(self._params)
