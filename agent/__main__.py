"""``python -m agent --host 127.0.0.1 --port 3100 --team NAME --unum N --type T``."""

import sys

from agent.runner import main

sys.exit(main())
