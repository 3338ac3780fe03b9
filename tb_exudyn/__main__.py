"""``python -m tb_exudyn`` is the ``tb-exudyn`` command."""

import sys

from .cli import main

sys.exit(main())
