"""``python -m symcable``: the command line (:mod:`symcable.cli.main`)."""
import sys

from .cli.main import main

sys.exit(main())
