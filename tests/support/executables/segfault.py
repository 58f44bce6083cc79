"""A test program that dies of a segmentation fault."""
import os
import signal
import sys

sys.stdin.read()
os.kill(os.getpid(), signal.SIGSEGV)
