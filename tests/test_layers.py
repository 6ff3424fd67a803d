"""The method-neutral layers: the parameter loader, options and intermediates declared by a method's entry,
the deprecated names, and the rule on private imports across subpackages (issue 19)."""

from __future__ import annotations

import ast
import json
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Mapping

import cv2
import numpy as np
import pytest

import depthrefine
from depthrefine.cli import build_parser, main
from depthrefine.io import depth_to_dtype
from depthrefine.methods import registry
from depthrefine.methods.intermediates import Intermediates, Picture
from depthrefine.methods.options import MethodOption, parse_count
from depthrefine.methods.params import params_from_mapping, params_to_dict

SRC = Path(depthrefine.__file__).resolve().parent


@dataclass(frozen=True)
class BlurParams:
    """A test method's parameters, one of which was removed."""

    radius: int = 1
    gain: float = 1.0
    removed_parameters: ClassVar[Mapping[str, str]] = {"clip_rounds": "always on", "margin": "0 pixels"}


def _blur(depth_lr, rgb_hr, *, params=None, progress=None):
    params = params or BlurParams()
    out = cv2.resize(depth_lr.astype(np.float32), rgb_hr.shape[1::-1], interpolation=cv2.INTER_NEAREST)
    return out * np.float32(params.gain)


def _blur_steps(depth_lr, rgb_hr, *, params=None, progress=None):
    depth_hr = _blur(depth_lr, rgb_hr, params=params)
    pictures = {"guide.png": Picture("color", rgb_hr, "the guide"),
                "halves.png": Picture("labels", (np.arange(rgb_hr.shape[1]) >= rgb_hr.shape[1] // 2)
                                      .astype(np.int16)[None].repeat(rgb_hr.shape[0], 0)),
                "samples.png": Picture("depth", depth_hr, "the result again", background=rgb_hr)}
    return depth_hr, Intermediates(pictures=pictures, arrays={"depth_hr": depth_hr}, record={"blur_radius": 1})


@pytest.fixture
def blur_method():
    """A registered test method with its own options (--radius, --gain) and an intermediates hook."""
    options = (MethodOption("--radius", "radius", "blur radius in pixels", type=parse_count, metavar="R"),
               MethodOption("--gain", "gain", "multiply the result", type=float, metavar="G"))
    entry = registry.register_method("blur", _blur, params_type=BlurParams, options=options,
                                     intermediates=_blur_steps, summary="test method", guided=False)
    try:
        yield entry
    finally:
        registry.METHODS.pop("blur", None)


@pytest.fixture
def files(tmp_path):
    rng = np.random.default_rng(3)
    depth = tmp_path / "depth.png"
    assert cv2.imwrite(str(depth), rng.integers(20, 200, (8, 12), dtype=np.uint8))
    color = tmp_path / "color.png"
    assert cv2.imwrite(str(color), rng.integers(0, 255, (32, 48, 3), dtype=np.uint8))
    return depth, color


# ---------------------------------------------------------------------------- the parameter loader


def test_a_removed_parameter_gets_one_line_saying_what_it_is_fixed_at():
    with pytest.raises(ValueError) as err:
        params_from_mapping(BlurParams, {"radius": 2, "clip_rounds": True}, source="parameter file p.toml")
    assert str(err.value) == ("parameter file p.toml: 'clip_rounds' is no longer a parameter of BlurParams "
                              "(it is fixed: always on); remove it.")


def test_unknown_keys_keep_their_message_and_known_keys_load():
    with pytest.raises(ValueError, match=r"^p: unknown parameter\(s\) 'radios' for BlurParams; known: radius, gain\.$"):
        params_from_mapping(BlurParams, {"radios": 2}, source="p")
    assert params_from_mapping(BlurParams, {"radius": 2}) == BlurParams(radius=2)
    assert params_to_dict(BlurParams(radius=2)) == {"radius": 2, "gain": 1.0}


def test_a_removed_key_in_a_params_file_is_exit_2(blur_method, files, tmp_path, capsys):
    depth, color = files
    toml = tmp_path / "p.toml"
    toml.write_text("radius = 2\nmargin = 1\n", encoding="utf-8")
    out = tmp_path / "o.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "blur", "--params", str(toml)]) == 2
    err = capsys.readouterr().err
    assert f"parameter file {toml}: 'margin' is no longer a parameter of BlurParams (it is fixed: 0 pixels)" in err
    assert len(err.strip().splitlines()) == 1 and not out.exists()


# ---------------------------------------------------------------------------- options from the entry


def test_a_methods_options_come_from_its_entry_in_a_group_of_their_own(blur_method, files, tmp_path, capsys):
    depth, color = files
    with pytest.raises(SystemExit):
        build_parser(["refine"]).parse_args(["refine", "--help"])
    help_text = capsys.readouterr().out
    assert "blur method options:" in help_text and "thesis method options:" in help_text
    assert help_text.index("blur method options:") < help_text.index("--radius R            blur radius in pixels")
    out = tmp_path / "o.npy"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "blur", "--gain", "0.5"]) == 0
    expected = _blur(cv2.imread(str(depth), cv2.IMREAD_UNCHANGED), np.zeros((32, 48, 3)), params=BlurParams(gain=0.5))
    np.testing.assert_array_equal(np.load(out), depth_to_dtype(expected, np.uint8))


def test_a_methods_option_with_another_method_is_exit_2(blur_method, files, tmp_path, capsys):
    depth, color = files
    out = tmp_path / "o.png"
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "bilinear", "--radius", "3"]) == 2
    assert "--radius sets parameters of the blur method; the method is 'bilinear': add --method blur." \
        in capsys.readouterr().err
    assert main(["refine", str(depth), str(color), "-o", str(out), "--method", "blur", "--clusters", "3"]) == 2
    assert "--clusters sets parameters of the thesis method; the method is 'blur': add --method thesis." \
        in capsys.readouterr().err
    assert not out.exists()


def test_options_must_set_fields_of_the_params_type():
    with pytest.raises(ValueError, match="setting fields of its params_type"):
        registry.register_method("blur-bad", _blur, params_type=BlurParams,
                                 options=(MethodOption("--sigma", "sigma", "no such field"),))
    assert "blur-bad" not in registry.METHODS
    with pytest.raises(ValueError, match="long option"):
        MethodOption("-s", "sigma", "short")


def test_the_light_option_specs_are_the_registry_entries():
    from depthrefine.methods._names import BUILTIN_OPTION_MODULES, registered_method_options

    import importlib

    for name, module in BUILTIN_OPTION_MODULES.items():
        assert registry.METHODS[name].options is importlib.import_module(module).OPTIONS
    assert registered_method_options()["thesis"] is registry.METHODS["thesis"].options


# ---------------------------------------------------------------------------- intermediates through the hook


def test_save_intermediate_writes_what_the_hook_gives(blur_method, files, tmp_path):
    depth, color = files
    folder = tmp_path / "steps"
    assert main(["refine", str(depth), str(color), "-o", str(tmp_path / "o.png"), "--method", "blur",
                 "--save-intermediate", str(folder)]) == 0
    names = {p.name for p in folder.iterdir()}
    assert names == {"result_colorized.png", "result_blended.png", "guide.png", "halves.png", "samples.png",
                     "intermediates.npz", "run.json"}
    guide = cv2.imread(str(folder / "guide.png"), cv2.IMREAD_UNCHANGED)
    np.testing.assert_array_equal(guide, cv2.imread(str(color), cv2.IMREAD_UNCHANGED))
    halves = cv2.imread(str(folder / "halves.png"), cv2.IMREAD_UNCHANGED)
    assert (halves[:, 0] != halves[:, -1]).any(axis=-1).all()  # two labels, two colors
    record = json.loads((folder / "run.json").read_text(encoding="utf-8"))
    assert record["method"] == "blur" and record["blur_radius"] == 1
    with np.load(folder / "intermediates.npz") as npz:
        assert npz["depth_hr"].shape == (32, 48)


def test_refine_intermediates_is_refine_bit_for_bit():
    depth = np.random.default_rng(0).integers(20, 200, (6, 8)).astype(np.uint8)
    rgb = np.random.default_rng(1).integers(0, 255, (24, 32, 3)).astype(np.uint8)
    params = depthrefine.ThesisParams(patches=(2, 1))
    depth_hr, steps = registry.refine_intermediates(depth, rgb, method="thesis", params=params)
    np.testing.assert_array_equal(depth_hr, depthrefine.refine(depth, rgb, method="thesis", params=params))
    assert steps.record["patches"] == [[0, 24, 0, 16], [0, 24, 16, 32]]
    assert registry.refine_intermediates(depth, rgb, method="bicubic")[1] is None


# ---------------------------------------------------------------------------- deprecated names


@pytest.mark.parametrize("module, old, new", [
    ("depthrefine", "RefineParams", "ThesisParams"),
    ("depthrefine.methods.thesis", "RefineParams", "ThesisParams"),
    ("depthrefine.methods.thesis.params", "RefineParams", "ThesisParams"),
    ("depthrefine", "Refinement", "Refinement"),
    ("depthrefine", "refine_with_intermediates", "refine_with_intermediates"),
])
def test_old_names_still_work_with_a_deprecation_warning(module, old, new):
    import importlib

    package = importlib.import_module(module)
    with pytest.warns(DeprecationWarning, match=f"{old} is deprecated"):
        value = getattr(package, old)
    assert value is getattr(importlib.import_module("depthrefine.methods.thesis"), new)
    assert old not in dir(package) and old not in getattr(package, "__all__", ())
    with pytest.warns(DeprecationWarning):  # every read warns (the old name is never cached)
        getattr(package, old)


def test_the_new_names_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        from depthrefine import GbpParams, ScaleWarning, ThesisParams  # noqa: F401
        from depthrefine.methods.thesis import Refinement, refine_with_intermediates  # noqa: F401


# ---------------------------------------------------------------------------- private imports


SHARED_PRIVATE = {"_validate", "_lazy", "_fill", "_numba", "_threads", "_native", "_names", "_picture", "_geodesic"}


def private_cross_package_imports(root: Path = SRC) -> list[str]:
    """``from X import Y`` across subpackages that names a private module or name (shared ones allowed).

    The subpackage of a module is its first folder under ``depthrefine/``
    (``methods``, ``rig``, ...; the modules directly in it form one more);
    every import counts, at module level or inside a function.
    """
    def package_of(parts: list[str]) -> str:
        return parts[0] if parts and (root / parts[0]).is_dir() else ""

    found = []
    for path in sorted(root.rglob("*.py")):
        parts = list(path.relative_to(root).with_suffix("").parts)
        folder = parts[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level:
                target = folder[:len(folder) - node.level + 1] + (node.module.split(".") if node.module else [])
            elif node.module and node.module.split(".")[0] == "depthrefine":
                target = node.module.split(".")[1:]
            else:
                continue
            if package_of(target) == package_of(folder if parts[-1] == "__init__" else parts):
                continue
            for alias in node.names:
                private = [p for p in [*target, alias.name] if p.startswith("_") and not p.startswith("__")]
                if private and not set(private) <= SHARED_PRIVATE:
                    found.append(f"{path.relative_to(root)}:{node.lineno}: from {'.'.join(target)} import {alias.name}")
    return found


def test_no_private_imports_across_subpackages():
    assert private_cross_package_imports() == []
