"""The ``redkin`` command line.  One module per command group; :mod:`redkin.cli.main` wires them."""
