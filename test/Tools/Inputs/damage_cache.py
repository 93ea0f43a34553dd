"""Damages every kernel-cache entry in a directory: damage_cache.py DIR MODE
MODE flip: inverts one byte in the middle; truncate: keeps the first 100."""
import glob
import os
import sys

directory, mode = sys.argv[1], sys.argv[2]
entries = glob.glob(os.path.join(directory, "*.oslk"))
if not entries:
    sys.exit("no cache entries in " + directory)
for path in entries:
    with open(path, "rb") as f:
        data = bytearray(f.read())
    if mode == "flip":
        data[len(data) // 2] ^= 0xFF
    else:
        data = data[:100]
    with open(path, "wb") as f:
        f.write(data)
