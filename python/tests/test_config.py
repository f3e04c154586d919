"""dloam.load_config and dloam.Config: presets, shipped configurations, keys and their checks."""

import pytest

import dloam


def test_preset_and_shipped_configuration():
    assert "HDL-64E" in dloam.sensor_presets()
    assert "kitti-raw" in dloam.shipped_configs()
    vlp = dloam.load_config(preset="VLP-16")
    assert vlp.preset == "VLP-16"
    assert vlp["sensor.N_scan"] == 16
    kitti = dloam.load_config(path="kitti-raw")
    # The shipped file sets the KITTI HDL-64E's beam offsets over the preset.
    assert isinstance(kitti.get("sensor.beam_vertical_offsets_m"), list)
    assert kitti.dump("sensor") != dloam.load_config().dump("sensor")


def test_a_file_over_a_preset(tmp_path):
    path = tmp_path / "mine.yaml"
    path.write_text("detection:\n  detector: geometric\nmapping:\n  every_n_scans: 2\n")
    config = dloam.load_config(preset="VLP-16", path=str(path))
    assert config["detection.detector"] == "geometric"
    assert config["mapping.every_n_scans"] == 2
    assert config["sensor.N_scan"] == 16


def test_set_is_checked_like_a_file():
    config = dloam.load_config()
    config["detection.detector"] = "none"
    assert config.get("detection.detector") == "none"
    config.set("deskew.enabled", False)
    assert config["deskew.enabled"] is False
    with pytest.raises(dloam.InputError, match="must be one of"):
        config["detection.detector"] = "fast"
    with pytest.raises(dloam.InputError, match="N_scna"):
        config["sensor.N_scna"] = 3
    with pytest.raises(KeyError):
        config.get("sensor.no_such_key")


def test_errors_name_the_problem(tmp_path):
    with pytest.raises(dloam.InputError, match="no-such-config"):
        dloam.load_config(path="no-such-config")
    with pytest.raises(dloam.InputError):
        dloam.load_config(preset="no-such-preset")
    bad = tmp_path / "bad.yaml"
    bad.write_text("sensor:\n  N_scan: -3\n")
    with pytest.raises(dloam.InputError, match="N_scan"):
        dloam.load_config(path=str(bad))


def test_data_dir_holds_the_shipped_files():
    import os

    assert os.path.isfile(os.path.join(dloam.data_dir(), "config", "default.yaml"))
