#!/usr/bin/env python3
"""Writes the tree of a git revision into a folder, like `git archive REV |
tar -x`, but skips blobs that the repository lacks (a partial mirror may not
hold large sample files) and lists them on stderr. Symbolic links are
recreated; submodules (gitlinks) are left empty.

Usage: export_git_tree.py REPO REV DEST
"""
import os
import subprocess
import sys


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    repo, rev, dest = sys.argv[1:]
    listing = subprocess.run(
        ["git", "-C", repo, "ls-tree", "-r", "-z", "--full-tree", rev],
        check=True, capture_output=True).stdout
    entries = []
    for record in listing.split(b"\0"):
        if not record:
            continue
        meta, path = record.split(b"\t", 1)
        mode, kind, sha = meta.split()
        if kind != b"blob":
            continue
        entries.append((mode.decode(), sha.decode(), path.decode()))
    batch = subprocess.Popen(["git", "-C", repo, "cat-file", "--batch"],
                             stdin=subprocess.PIPE, stdout=subprocess.PIPE)
    missing = []
    for mode, sha, path in entries:
        batch.stdin.write((sha + "\n").encode())
        batch.stdin.flush()
        header = batch.stdout.readline().split()
        if len(header) < 2 or header[1] == b"missing":
            missing.append(path)
            continue
        size = int(header[2])
        data = batch.stdout.read(size)
        batch.stdout.read(1)  # the newline after the object
        target = os.path.join(dest, path)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        if mode == "120000":
            os.symlink(data.decode(), target)
            continue
        with open(target, "wb") as out:
            out.write(data)
        if mode == "100755":
            os.chmod(target, 0o755)
    batch.stdin.close()
    batch.wait()
    for path in missing:
        print(f"export_git_tree: {rev}:{path} is not in {repo}; skipped",
              file=sys.stderr)
    print(f"export_git_tree: {len(entries) - len(missing)} files of {rev} "
          f"written to {dest}, {len(missing)} missing")


if __name__ == "__main__":
    main()
