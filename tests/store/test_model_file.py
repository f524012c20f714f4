"""Writing a simplified model (gd_analyze.store.model_file.save_model): an argument that is
not a model is one line naming it, and nothing is written."""

import pytest

import gd_analyze as gd
from gd_analyze.errors import InputError
from gd_analyze.store.model_file import save_model


@pytest.mark.parametrize("model", [None, {}, "simplified_model.json"])
def test_save_model_refuses_what_is_not_a_model(tmp_path, model):
    """A dict or None raised AttributeError ("'dict' object has no attribute 'to_dict'")."""
    assert gd.save_model is save_model
    with pytest.raises(InputError) as e:
        save_model(model, tmp_path / "m.json")
    assert str(e.value) == f"model: a SimplifiedModel, not a {type(model).__name__}"
    assert list(tmp_path.iterdir()) == []
