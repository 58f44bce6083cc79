"""A test program that answers prose instead of triangles."""
import sys

sys.stdin.read()
print("triangulation complete: 42 triangles")
