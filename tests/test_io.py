"""The shared output-path check: names the file and the caller's remedy."""

import pytest

from armkit._io import check_output_path
from armkit.errors import InputError


def test_check_output_path(tmp_path):
    existing = tmp_path / "a.csv"
    existing.write_text("x")
    assert check_output_path(tmp_path / "new.csv", False) == tmp_path / "new.csv"
    assert check_output_path(existing, True) == existing
    with pytest.raises(InputError, match=r"'.*a\.csv' already exists; pass overwrite=True to replace it"):
        check_output_path(existing, False)
    with pytest.raises(InputError, match="already exists; pass --force to replace it"):
        check_output_path(existing, False, remedy="pass --force")
    with pytest.raises(InputError, match="is a folder"):
        check_output_path(tmp_path, True)
    with pytest.raises(InputError, match="folder .* does not exist"):
        check_output_path(tmp_path / "missing" / "a.csv", True)
