#!/usr/bin/python3
"""The install list brings in everything the project uses (check_install_list.py), and the check
names what a list that lacks a package would leave out: header or tool, package, using file."""
import os
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.realpath(__file__))
ROOT = os.path.dirname(HERE)
CHECK = os.path.join(HERE, "check_install_list.py")
LIST = os.path.join(ROOT, "scripts", "debian-packages.txt")


def run_check(list_file=LIST):
    r = subprocess.run([sys.executable, CHECK, "--root", ROOT, "--list", list_file],
                       capture_output=True, text=True)
    return r.returncode, r.stdout + r.stderr


def without(package):
    lines = [l for l in open(LIST) if l.strip() != package]
    f = tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False)
    f.writelines(lines)
    f.close()
    return f.name


class InstallList(unittest.TestCase):
    def test_list_covers_every_header_tool_and_module(self):
        code, out = run_check()
        print(out)
        self.assertEqual(code, 0, out)

    def test_missing_header_package_is_named(self):
        # The fault that reached a fresh machine: CLI11 installed by hand, not listed.
        path = without("libcli11-dev")
        code, out = run_check(path)
        os.unlink(path)
        print(out)
        self.assertEqual(code, 1)
        line = [l for l in out.splitlines() if "CLI/CLI.hpp" in l]
        self.assertTrue(line, out)
        self.assertIn("libcli11-dev", line[0])
        self.assertIn("bench/cloth_vs_bullet.cpp", line[0])

    def test_missing_tool_package_is_named(self):
        path = without("xvfb")
        code, out = run_check(path)
        os.unlink(path)
        print(out)
        self.assertEqual(code, 1)
        line = [l for l in out.splitlines() if "tool Xvfb" in l]
        self.assertTrue(line, out)
        self.assertIn("xvfb", line[0])
        self.assertIn("scripts/demo.sh", line[0])

    def test_missing_launch_node_package_is_named(self):
        path = without("rviz")
        code, out = run_check(path)
        os.unlink(path)
        self.assertEqual(code, 1)
        line = [l for l in out.splitlines() if "launch node rviz/rviz" in l]
        self.assertTrue(line, out)
        self.assertIn("launch/demo.launch", line[0])


if __name__ == "__main__":
    unittest.main(verbosity=2)
