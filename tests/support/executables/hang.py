"""A test program that never answers."""
import sys
import time

sys.stdin.read()
while True:
    time.sleep(1)
