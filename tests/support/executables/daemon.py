"""A test program that answers correctly but leaves a daemon running in a session of its own
(its pid written to the file named by DAEMON_PID_FILE, else vorobench-daemon.pid in the temp folder)."""
import os
import subprocess
import tempfile
import sys

data = sys.stdin.buffer.read()
child = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(1000)"], start_new_session=True,
                         stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
with open(os.environ.get("DAEMON_PID_FILE", os.path.join(tempfile.gettempdir(), "vorobench-daemon.pid")), "w") as f:
    f.write(str(child.pid))
subprocess.run([sys.executable, "scipy_delaunay.py"], input=data, check=True)
