"""Plain helpers the tests import by package path (``from tests.support.srs_arms import arm``).

They are here, not in fixtures, because tests use them when pytest collects them: in
``@pytest.mark.parametrize`` lists and hypothesis strategies.  Built objects shared by
test bodies are fixtures in ``tests/conftest.py``.
"""
