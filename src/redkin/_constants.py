"""Sizes and names that the library checks and the command line's help states, each defined here once.

They live in a module that imports nothing, so that ``redkin --help`` and each command's ``--help`` can state them
without importing the packages that use them (and numba, scipy and the compiled kernels with those).  Each module
that uses one imports it from here under its own name: ``redkin.workspace.grid.MAX_RESOLUTION`` is
:data:`WORKSPACE_MAX_RESOLUTION`.
"""

#: Largest length (metres) a robot description or a pose may hold: far beyond any arm, far below where squares
#: overflow (:mod:`redkin._validation`, and :func:`redkin._pose_kernels.pose_defect` in the kernels).
MAX_LENGTH = 1e6
#: Most grid points per axis of a workspace map (``redkin workspace --resolution``; :mod:`redkin.workspace.grid`).
WORKSPACE_MAX_RESOLUTION = 1000
#: Most orientations a workspace map may take (``redkin workspace --orientations``;
#: :mod:`redkin.workspace.orientations`).
WORKSPACE_MAX_ORIENTATIONS = 20_000
#: Most poses a workspace map may take, grid points times orientations (about 7 core-hours at 2.7 us a pose: the
#: measure of :data:`redkin.workspace.grid.CHUNK_POSES`' chunks; :mod:`redkin.workspace.grid`).
WORKSPACE_MAX_POSES = 10**10
#: Most chunks a workspace map may be cut into (Dask tasks and marker files; :mod:`redkin.workspace.grid`).
WORKSPACE_MAX_CHUNKS = 10**6
#: The file name of the map inside the output directory of ``redkin workspace`` (:mod:`redkin.workspace.store`).
WORKSPACE_MAP_NAME = "map.zarr"
#: Largest number of grid points along one axis of a torso-arm map, 10^6 points in all (``redkin torso-arm map
#: --resolution``; :mod:`redkin.torso_arm.maps`).
TORSO_ARM_MAX_RESOLUTION = 1000
#: The velocity IK methods by name (``redkin track --method``; :func:`redkin.velocity.make_method`).
VELOCITY_METHOD_NAMES = ("sc", "pinv", "dls", "dls-adaptive")
#: Largest step budget of one virtual-arms run, every accepted step being recorded (``redkin virtual-arms
#: --max-steps``; :mod:`redkin.virtual_arms.generate`).
VIRTUAL_ARMS_MAX_STEPS = 1_000_000
#: The ending of a workspace map's file being written (renamed to its own name once whole; a run removes those it
#: finds): :mod:`redkin.workspace._durable` writes them, :mod:`redkin.workspace.store` removes them.
PARTIAL_SUFFIX = ".partial"
