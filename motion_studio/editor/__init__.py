"""The motion editor: an editing session (``session``), IK handles, a physics preview and a local web app.

Light imports only here; the web edge (``server``), the scene (``scene``) and the preview load on use.
"""

from motion_studio.editor.errors import EditorError
from motion_studio.editor.session import EditorSession

__all__ = ["EditorError", "EditorSession"]
