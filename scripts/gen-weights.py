#!/usr/bin/env python3
"""Writes a seeded weight file (.csv) for a map: terrain patches of one weight each.

usage: scripts/gen-weights.py WIDTH HEIGHT PATCH SEED MAX_WEIGHT > weights.csv

Every PATCH x PATCH block of cells gets one weight from 1 to MAX_WEIGHT, drawn with a
xorshift64 generator seeded with SEED, so the file is a pure function of the arguments.
maps/weighted/arena-weights.csv is `scripts/gen-weights.py 49 49 7 32 9`.
"""
import sys


def main() -> None:
    width, height, patch, seed, top = (int(a) for a in sys.argv[1:6])
    state = seed | 1
    mask = (1 << 64) - 1

    def draw() -> int:
        nonlocal state
        state ^= (state << 13) & mask
        state ^= state >> 7
        state ^= (state << 17) & mask
        return state

    cols, rows = -(-width // patch), -(-height // patch)
    weights = [1 + draw() % top for _ in range(cols * rows)]
    print(f"# {width}x{height} weights, {patch}x{patch} patches of 1..{top}, seed {seed}")
    for y in range(height):
        print(",".join(str(weights[(y // patch) * cols + x // patch]) for x in range(width)))


if __name__ == "__main__":
    main()
