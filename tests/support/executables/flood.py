"""A test program that prints a 10 GB answer (as fast as the pipe takes it)."""
import sys

sys.stdin.read()
block = "0 1 2\n" * 100_000
for _ in range(10 * 2 ** 30 // len(block)):
    sys.stdout.write(block)
