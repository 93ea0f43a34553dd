#!/usr/bin/env python3
"""Checks test/conformance/status.txt against the corpus manifest.

  inventory.py --corpus DIR --status FILE [--markdown]

Every manifest test must appear exactly once, as `pass` or as `not-yet`
with a reason; names the manifest does not have are errors. With
--markdown, prints the pass count and the table of reasons (the README's).
"""
import argparse
import collections
import json
import os
import sys


def read_status(path):
    entries = []
    for number, line in enumerate(open(path), 1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        parts = line.split(None, 2)
        if parts[1:2] == ["pass"] and len(parts) == 2:
            entries.append((number, parts[0], "pass", ""))
        elif parts[1:2] == ["not-yet"] and len(parts) == 3:
            entries.append((number, parts[0], "not-yet", parts[2]))
        else:
            raise SystemExit("%s:%d: expected 'NAME pass' or 'NAME not-yet REASON'" % (path, number))
    return entries


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--corpus", required=True)
    ap.add_argument("--status", required=True)
    ap.add_argument("--markdown", action="store_true")
    a = ap.parse_args()
    manifest = [t["name"] for t in json.load(open(os.path.join(a.corpus, "manifest.json")))]
    entries = read_status(a.status)
    errors = []
    seen = collections.Counter(name for _, name, _, _ in entries)
    for name, count in seen.items():
        if count > 1:
            errors.append("%s is listed %d times" % (name, count))
        if name not in manifest:
            errors.append("%s is not a test of the manifest" % name)
    for name in manifest:
        if name not in seen:
            errors.append("%s (in the manifest) has no status" % name)
    if errors:
        print("\n".join(errors))
        return 1
    passing = [n for _, n, s, _ in entries if s == "pass"]
    print("%d of %d conformance tests pass; %d are not yet supported" %
          (len(passing), len(manifest), len(manifest) - len(passing)))
    if a.markdown:
        by_reason = collections.OrderedDict()
        for _, name, status, reason in entries:
            if status == "not-yet":
                by_reason.setdefault(reason, []).append(name)
        print("\n| tests | why not yet |\n|---|---|")
        for reason, names in by_reason.items():
            print("| %s | %s |" % (", ".join(names), reason))
    return 0


if __name__ == "__main__":
    sys.exit(main())
