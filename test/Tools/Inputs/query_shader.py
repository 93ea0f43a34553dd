"""Prints a shader's interface through python/oslquery.py, one line per
parameter: flags, type, name, value, space, then its metadata."""
import sys

import oslquery


def show(p, indent):
    flags = "".join(f for f, on in (("out ", p.isoutput), ("closure ", p.isclosure),
                                    ("varlen ", p.varlenarray),
                                    ("nodefault ", not p.validdefault)) if on)
    if p.isstruct:
        print("%s%sstruct %s %s fields=%s" % (indent, flags, p.structname, p.name,
                                              list(p.fields)))
    else:
        print("%s%s%s %s = %r%s" % (indent, flags, p.type, p.name, p.value,
                                    " in " + p.spacename if p.spacename else ""))
    for m in p.metadata:
        show(m, indent + "  meta ")


q = oslquery.OSLQuery(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else "")
if not q.shadername():
    print("error:", q.geterror())
    sys.exit(1)
print(q.shadertype(), q.shadername(), len(q))
for m in q.metadata:
    show(m, "shader meta ")
for p in q:
    show(p, "")
print("by name:", q.getparam("gain").type, q["gain"].value, q.getparam("nothing"))
print("type equals text:", q[0].type == "float", q[0].type != "color")
