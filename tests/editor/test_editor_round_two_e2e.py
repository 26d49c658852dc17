"""The real editor under Xvfb with Mesa (issue 15, the bugs a new user hit): scripted sessions on
the Cornell box. EditorDeleteKey: Del deletes the selection when the viewport or the outliner has
the keyboard (keyboard navigation made ImGui's WantCaptureKeyboard always true, so it never did),
and not when another panel does.

Environment: CAUSTIC_BIN (build/caustic), CAUSTIC_SOURCE_DIR. Needs xvfb-run (Debian: xvfb xauth).
"""
import json
import os
import shutil
import unittest

from test_editor_e2e import CORNELL, EditorSessionCase, run_editor

DELETE_SCRIPT = """
wait_samples 1
select object "small box"
# The inspector has the keys: Del is not a delete there.
focus inspector
key Delete
expect_undo_steps 0
expect_count objects {n}
# The viewport: the small box goes, one undo step.
focus viewport
key Delete
expect_undo_steps 1
expect_count objects {m}
undo
expect_count objects {n}
# The outliner, likewise.
select object "small box"
focus outliner
key Delete
expect_undo_steps 1
expect_count objects {m}
quit
"""


class EditorDeleteKey(EditorSessionCase):
    @classmethod
    def setUpClass(cls):
        cls.make_tmp("caustic-editor-delete-")
        shutil.copy(CORNELL, os.path.join(cls.tmp, "scene.json"))
        with open(CORNELL) as f:
            n = len(json.load(f)["objects"])
        with open(os.path.join(cls.tmp, "script.txt"), "w") as f:
            f.write(DELETE_SCRIPT.format(n=n, m=n - 1))
        cls.editor = run_editor(cls.tmp, "script.txt", os.path.join(cls.tmp, "scene.json"))

    def test_delete_key(self):
        self.assertEqual(self.editor.returncode, 0, self.editor.stderr)


if __name__ == "__main__":
    unittest.main()
