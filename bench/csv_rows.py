"""Shared by the bench/ helper scripts: a row appended to a CSV table."""
import csv
import os


def append_row(path, row):
    """Appends `row` (a dict) to the CSV at `path`, writing the header first if it is new."""
    new = not os.path.exists(path)
    with open(path, "a", newline="") as out:
        writer = csv.DictWriter(out, fieldnames=list(row))
        if new:
            writer.writeheader()
        writer.writerow(row)
