"""The viscera CLI's small courtesies, in a private network namespace: clear errors for a
create without a scene and a rate above the servers' cap, --version, and each command's help
with examples and without the six common options (listed once by `viscera --help`, and still
accepted after any command)."""
import os
import subprocess
import unittest

import tempfile

from netns_support import PUSH_SCENE, URL, Server, new_client, require_private_netns, wait_for_servers

CLI = os.environ["VISCERA_CLI"]


def viscera(*args):
    return subprocess.run([CLI, *args], capture_output=True, text=True, timeout=60)


class CliTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        require_private_netns()

    def test_create_without_a_scene_says_what_it_needs(self):
        r = viscera("create", "--lcm-url", URL)
        self.assertEqual(r.returncode, 1)
        self.assertIn("create needs a scene: a SCENE name from the server's scene directory "
                      "(viscera create cavity) or --scene-file FILE", r.stderr)
        r = viscera("create", "cavity", "--scene-file", "x.toml", "--lcm-url", URL)
        self.assertIn("not both", r.stderr)

    def test_rate_is_capped_like_the_server(self):
        r = viscera("create", "cavity", "--rate", "5000", "--lcm-url", URL)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("1000", r.stderr)

    def test_version(self):
        r = viscera("--version")
        self.assertEqual(r.returncode, 0)
        self.assertRegex(r.stdout, r"^viscera \d+\.\d+\.\d+")

    def test_help_has_examples_and_no_repeated_common_options(self):
        top = viscera("--help").stdout
        self.assertIn("--lcm-url", top)
        for command in ("status", "create", "haptic", "servers"):
            text = viscera(command, "--help").stdout
            self.assertIn("Examples:", text, command)
            self.assertNotIn("--lcm-url TEXT", text, command)
            self.assertIn("Common options (--lcm-url, --key-file, --sessions, --timeout, --json): "
                          "viscera --help", text)

    def test_common_options_still_work_after_a_command(self):
        r = viscera("servers", "--timeout", "0.3", "--json", "--lcm-url", URL)
        self.assertEqual(r.returncode, 2, r.stderr)  # none heard: kNoServer, not a parse error
        self.assertIn("no server answered", r.stderr)


class CliRefusalTest(unittest.TestCase):
    """The server's refusals of bad scenes, as the CLI prints them: the user's own file named,
    with the line and a suggestion for a typo."""

    @classmethod
    def setUpClass(cls):
        require_private_netns()
        cls.server = Server("py-cli", "--max-sessions", "2")
        wait_for_servers(new_client(), ["py-cli"])
        cls.dir = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        assert cls.server.stop() == 0, cls.server.stderr()
        cls.dir.cleanup()

    def test_an_unknown_scene_and_a_typo_are_named(self):
        r = viscera("create", "nope", "--server", "py-cli", "--lcm-url", URL)
        self.assertEqual(r.returncode, 4, r.stderr)  # refused
        self.assertIn("nope", r.stderr)
        typo = os.path.join(self.dir.name, "my_scene.toml")
        with open(PUSH_SCENE) as f:
            text = f.read()
        with open(typo, "w") as f:
            f.write(text.replace("[intestine]", "[intestine]\nlenght = 1.0", 1))
        r = viscera("create", "--scene-file", typo, "--server", "py-cli", "--lcm-url", URL)
        self.assertEqual(r.returncode, 4, r.stderr)
        self.assertIn(typo, r.stderr)
        self.assertNotIn("<inline>", r.stderr)
        self.assertRegex(r.stderr, r"intestine\.lenght = 1(\.0)? \(line \d+\): unknown key; "
                                   r"did you mean \"length\"\?")


if __name__ == "__main__":
    unittest.main()
