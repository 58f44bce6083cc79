"""A test program whose grandchild does the work (and burns 0.4 s of CPU) while the program
itself exits at once: the harness must still count that CPU time."""
import os
import sys
import time

data = sys.stdin.buffer.read()
if os.fork() == 0:
    if os.fork() == 0:                      # the grandchild, orphaned at once
        os.setsid()
        from io import BytesIO
        sys.stdin = __import__("io").TextIOWrapper(BytesIO(data))
        deadline = time.process_time() + 0.4
        while time.process_time() < deadline:
            pass
        import scipy_delaunay  # noqa: F401  (prints the triangles)
        sys.stdout.flush()
        os._exit(0)
    os._exit(0)
os.wait()
