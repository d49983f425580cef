"""``method='rembg'``: a learned network through rembg's sessions, without any real network's weights.

The network here is a 1x1 convolution built in the test ("red minus green",
then a sigmoid): rembg's IS-Net sessions (``isnet-general-use``,
``dis_custom``) feed it the photo scaled to [0, 1] by its own maximum, less
0.5, so a pixel's logit is proportional to its red minus its green and the
object's edge is where they are equal, at the disk's true edge.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

from attneave.stimuli.errors import InputError
from attneave.stimuli.extraction import extract
from attneave.stimuli.render import coverage

pytest.importorskip("rembg.sessions")


def _disk(shape, cx, cy, r):
    th = np.linspace(0, 2 * np.pi, 1024, endpoint=False)
    return coverage(np.c_[cx + r * np.cos(th), cy + r * np.sin(th)], shape)


def _red_on_green(cov):
    """Red where `cov` is 1, green where 0; red = green exactly at coverage 0.5."""
    img = np.empty(cov.shape + (3,), np.uint8)
    img[..., 0] = np.round(40 + 160 * cov)
    img[..., 1] = np.round(200 - 160 * cov)
    img[..., 2] = 90
    return img


def _tiny_network(path, gain=8.0):
    """1x1 convolution 'red minus green' and a sigmoid, any input size; a low `gain` hesitates."""
    onnx = pytest.importorskip("onnx")
    from onnx import TensorProto, helper, numpy_helper

    w = numpy_helper.from_array(np.array([[[[gain]], [[-gain]], [[0.0]]]], np.float32), "w")
    graph = helper.make_graph(
        [helper.make_node("Conv", ["input", "w"], ["z"]), helper.make_node("Sigmoid", ["z"], ["p"])],
        "tiny", [helper.make_tensor_value_info("input", TensorProto.FLOAT, [1, 3, "h", "w"])],
        [helper.make_tensor_value_info("p", TensorProto.FLOAT, [1, 1, "h", "w"])], [w],
    )
    model = helper.make_model(graph, opset_imports=[helper.make_opsetid("", 13)])
    model.ir_version = 8
    onnx.save(model, str(path))
    return path


@pytest.fixture
def home(tmp_path, monkeypatch):
    """rembg's weights directory, empty, and every download refused loudly."""
    import pooch

    d = tmp_path / "u2net"
    d.mkdir()
    monkeypatch.setenv("U2NET_HOME", str(d))
    monkeypatch.delenv("REMBG_HOME", raising=False)

    def no_download(*args, **kwargs):
        raise AssertionError("rembg tried to download weights")

    monkeypatch.setattr(pooch, "retrieve", no_download)
    return d


def _write(path, img):
    import cv2

    cv2.imwrite(str(path), img[:, :, ::-1])
    return path


def test_a_model_file_through_rembgs_custom_session_traces_the_probability_at_half(tmp_path, home):
    net = _tiny_network(tmp_path / "tiny.onnx")  # outside rembg's home: the user's own file is accepted
    img = _red_on_green(_disk((120, 160), 80.3, 60.2, 35))
    ex = extract(img, method="rembg", model={"network": "dis_custom", "model_file": net})
    cx, cy = ex.contour.centroid
    # sub-pixel: the map is 1024 px, brought back to 160x120, traced at 0.5
    assert abs(cx - 80.3) < 0.3 and abs(cy - 60.2) < 0.3
    assert ex.contour.area == pytest.approx(np.pi * 35**2, rel=0.02)
    assert ex.params["rembg_model"] == "dis_custom" and ex.params["level"] == 0.5
    assert 0 < ex.params["uncertainty"] < 0.2


def test_named_network_reads_the_weights_already_in_u2net_home_and_never_downloads(tmp_path, home):
    img = _red_on_green(_disk((120, 160), 80.3, 60.2, 35))
    with pytest.raises(InputError, match=r"no isnet-general-use\.onnx in .*--model-file") as exc:
        extract(img, method="rembg")  # the default network, whose file is not here
    assert "\n" not in str(exc.value) and "never downloads" in str(exc.value)
    _tiny_network(home / "isnet-general-use.onnx")
    ex = extract(img, method="rembg")
    assert ex.params["rembg_model"] == "isnet-general-use" and ex.params["model_file"] is None
    assert ex.contour.area == pytest.approx(np.pi * 35**2, rel=0.02)


def test_a_box_is_honoured_and_nothing_outside_it_is_kept(tmp_path, home):
    net = _tiny_network(tmp_path / "tiny.onnx")
    model = {"network": "dis_custom", "model_file": net}
    cov = np.maximum(_disk((120, 160), 50.3, 60.2, 30), _disk((120, 160), 127.6, 40.4, 14))
    img = _red_on_green(cov)
    whole = extract(img, method="rembg", model=model)
    assert whole.contour.centroid[0] < 80  # the larger disk
    boxed = extract(img, method="rembg", model=model, boxes=[(111, 24, 33, 33)])
    cx, cy = boxed.contour.centroid
    assert abs(cx - 127.6) < 0.3 and abs(cy - 40.4) < 0.3 and boxed.params["mode"] == "box"
    # a box cutting the large disk in half: the outline stays inside the box
    cut = extract(img, method="rembg", model=model, boxes=[(15, 20, 35, 80)])
    pts = cut.contour.points
    assert pts[:, 0].min() >= 15 - 0.5 and pts[:, 0].max() <= 50 + 0.5
    assert pts[:, 1].min() >= 20 - 0.5 and pts[:, 1].max() <= 100 + 0.5


def test_a_box_without_object_falls_back_to_grabcut_not_to_a_rescaled_mask(tmp_path, home):
    # rembg's own mask image is stretched to each map's range, so an empty box would show its
    # least unlikely pixels as an object; the network's probabilities say there is none
    net = _tiny_network(tmp_path / "tiny.onnx")
    cov = _disk((120, 160), 80.3, 60.2, 25)
    img = np.empty(cov.shape + (3,), np.uint8)
    img[..., 0] = 40
    img[..., 1] = np.round(220 - 160 * cov)
    img[..., 2] = np.round(40 + 160 * cov)  # a blue disk on green: never as red as green
    ex = extract(img, method="rembg", model={"network": "dis_custom", "model_file": net}, boxes=[(50, 30, 61, 61)])
    assert ex.params["resolved"] == "photo" and ex.params["model_found_nothing"]


def test_cli_rembg_runs_and_its_outline_is_never_ok_without_a_box(tmp_path, home):
    import pandas as pd

    from attneave.cli import main

    net = _tiny_network(tmp_path / "tiny.onnx")
    photo = _write(tmp_path / "red.png", _red_on_green(_disk((120, 160), 80.3, 60.2, 35)))
    out = tmp_path / "out"
    assert main(["extract", str(photo), "-o", str(out), "--method", "rembg", "--rembg-model", "dis_custom",
                 "--model-file", str(net)]) == 0
    s = pd.read_csv(out / "summary.csv")
    assert s.loc[0, "method"] == "rembg" and s.loc[0, "status"] == "suspect" and s.loc[0, "uncertainty"] > 0


@pytest.mark.parametrize("extra, message", [
    (["--rembg-model", "u2net"], "--rembg-model applies to --method rembg only"),
    (["--method", "rembg", "--rembg-model", "nonet"], "unknown rembg network 'nonet'; rembg knows"),
    (["--method", "rembg", "--rembg-model", "withoutbg"], "not usable here (it sends the photo"),
    (["--method", "rembg", "--rembg-model", "sam"], "not usable here"),
    (["--method", "rembg", "--rembg-model", "u2net_custom"], "reads a file of yours: give it with --model-file"),
    (["--method", "rembg"], "'isnet-general-use': no isnet-general-use.onnx in"),
    (["--method", "rembg", "--model-file", "text.onnx"], "text.onnx: not usable as rembg's 'isnet-general-use'"),
    (["--method", "rembg", "--model-size", "320"], "--model-size applies to --method model only"),
])
def test_cli_rembg_mistakes_are_one_line_before_any_output(tmp_path, home, capsys, extra, message):
    from attneave.cli import main

    photo = _write(tmp_path / "a.png", _red_on_green(_disk((120, 160), 80.3, 60.2, 35)))
    (tmp_path / "text.onnx").write_text("not a network\n")
    extra = [str(tmp_path / e) if e.endswith(".onnx") else e for e in extra]
    assert main(["extract", str(photo), "-o", str(tmp_path / "o"), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err
    assert not (tmp_path / "o").exists()


def test_without_rembg_installed_the_message_says_how_to_get_it(tmp_path, monkeypatch, capsys):
    from attneave.cli import main

    for mod in [m for m in sys.modules if m == "rembg" or m.startswith("rembg.")]:
        monkeypatch.delitem(sys.modules, mod)
    monkeypatch.setitem(sys.modules, "rembg", None)  # import rembg -> ImportError
    photo = _write(tmp_path / "a.png", _red_on_green(_disk((120, 160), 80.3, 60.2, 35)))
    assert main(["extract", str(photo), "-o", str(tmp_path / "o"), "--method", "rembg"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and 'pip install "attneave[rembg]"' in err
    with pytest.raises(InputError, match="needs rembg"):
        extract(_red_on_green(_disk((60, 80), 40, 30, 15)), method="rembg")


def test_a_learned_outline_from_a_box_is_ok_only_by_the_learned_rule(tmp_path, home, monkeypatch):
    from attneave.stimuli.extraction import verdict
    from attneave.stimuli.extraction.verdict import judge

    model = {"network": "dis_custom", "model_file": _tiny_network(tmp_path / "crisp.onnx")}
    img = _red_on_green(_disk((120, 160), 80.3, 60.2, 35))
    box = [(35, 15, 91, 91)]  # the disk and a margin, as a person draws a box
    crisp = extract(img, method="rembg", model=model, boxes=box)
    assert judge(img, crisp).status == "ok"
    assert "cannot be verified" in judge(img, extract(img, method="rembg", model=model)).reason  # no box
    # the same disk grazing the image's left edge (3 % of its outline, under the frame reason's 5 %):
    # the learned rule wants no contact at all, and that is the only reason
    grazing = _red_on_green(_disk((120, 160), 35.3, 60.2, 35))
    v = judge(grazing, extract(grazing, method="rembg", model=model, boxes=[(0, 15, 81, 91)]))
    assert 0 < v.measures["frame"] < 0.05
    assert v.status == "suspect" and v.reasons == ["figure-ground of a photograph (rembg) cannot be verified: "
                                                   "check the overlay"]
    # no rule, no ok
    monkeypatch.setattr(verdict, "LEARNED_RULES", {})
    assert "cannot be verified" in judge(img, crisp).reason


def test_uncertainty_measures_a_hesitant_network(tmp_path, home):
    from attneave.stimuli.extraction.verdict import judge

    img = _red_on_green(_disk((120, 160), 80.3, 60.2, 35))
    box = [(35, 15, 91, 91)]
    crisp = extract(img, method="rembg", model={"network": "dis_custom", "model_file": _tiny_network(
        tmp_path / "crisp.onnx")}, boxes=box)
    # a network whose probability climbs over a wide band of colours: the same outline, undecided
    soft = extract(img, method="rembg", model={"network": "dis_custom", "model_file": _tiny_network(
        tmp_path / "soft.onnx", gain=0.5)}, boxes=box)
    assert soft.contour.area == pytest.approx(crisp.contour.area, rel=0.02)
    assert soft.params["uncertainty"] > 5 * crisp.params["uncertainty"]
    assert judge(img, soft).measures["uncertainty"] == soft.params["uncertainty"]
