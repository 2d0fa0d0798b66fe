"""``python -m feeddrive.cli``: the ``feeddrive`` command."""

import sys

from . import main

sys.exit(main())
