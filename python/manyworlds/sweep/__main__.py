import sys

from manyworlds.sweep.cli import main

sys.exit(main())
