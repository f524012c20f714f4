"""Writing and reading a simplified model (gd_analyze.store.model_file): an argument that is
not a model or not a file name is one line naming it, and nothing is written."""

import pytest

import gd_analyze as gd
from gd_analyze.errors import InputError
from gd_analyze.simplify.choices import full_choices
from gd_analyze.simplify.simplified import SimplifiedModel
from gd_analyze.store.model_file import load_model, save_model


@pytest.mark.parametrize("model", [None, {}, "simplified_model.json"])
def test_save_model_refuses_what_is_not_a_model(tmp_path, model):
    """A dict or None raised AttributeError ("'dict' object has no attribute 'to_dict'")."""
    assert gd.save_model is save_model
    with pytest.raises(InputError) as e:
        save_model(model, tmp_path / "m.json")
    assert str(e.value) == f"model: a SimplifiedModel, not a {type(model).__name__}"
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("path", [None, 3, b"m.json"])
def test_a_file_argument_that_is_not_a_path_is_one_line_naming_it(tmp_path, monkeypatch, path):
    """load_model(None) said "None: no such file" (None read as a file named None), and
    save_model(model, None) raised a bare TypeError from opening it."""
    monkeypatch.chdir(tmp_path)
    model = SimplifiedModel(gd.load_robot("two-link"), full_choices(2), 0.9, 0.01)
    kind = type(path).__name__
    with pytest.raises(InputError, match=rf"^path: a JSON file \(str or os.PathLike\), not a "
                                         rf"{kind}$"):
        save_model(model, path)
    with pytest.raises(InputError, match=rf"^path: a simplified-model JSON file \(str or "
                                         rf"os.PathLike\), not a {kind}$"):
        load_model(path)
    assert list(tmp_path.iterdir()) == []
    save_model(model, tmp_path / "m.json")          # a path is still one
    assert load_model(str(tmp_path / "m.json")).choices == model.choices


@pytest.mark.parametrize("name, said", [(".", "is a folder: give a file name"),
                                        ("", "no file name"),
                                        ("no folder/m.json", "its folder does not exist")])
def test_a_destination_that_cannot_be_a_file_is_one_line(tmp_path, monkeypatch, name, said):
    """save_model(model, "/tmp") raised IsADirectoryError from the rename (after writing its
    temporary file beside /tmp, in /), "" OSError "Device or resource busy" and a missing
    folder FileNotFoundError; nothing is written."""
    monkeypatch.chdir(tmp_path)
    model = SimplifiedModel(gd.load_robot("two-link"), full_choices(2), 0.9, 0.01)
    with pytest.raises(InputError, match=f": {said}$"):
        save_model(model, name)
    assert list(tmp_path.iterdir()) == []
