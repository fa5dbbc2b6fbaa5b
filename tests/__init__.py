"""redkin's tests: one ``test_<package>_<module>.py`` per module of ``src/redkin`` (flat), shared pieces in
``support/``."""
