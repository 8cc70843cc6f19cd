"""relief.simulate steps an MLHM scene's erosion as `relief simulate` does: the same seed and
steps give the bytes the command line writes (whatever the thread count), the stepped scene
renders as `relief render` renders the command line's output, and its state reads as
NumPy arrays."""

import os
import subprocess
import threading

import numpy as np
import pytest

import relief


@pytest.fixture
def rivers(tmp_path, run_relief):
    path = tmp_path / "rivers.json"
    run_relief("generate", "mlhm", "--scene", "rivers-rain", "--size", "24", "-o", path)
    return path


def cli_simulate(relief_bin, scene, out, *args, threads=1):
    """`relief simulate` with RAYON_NUM_THREADS=threads."""
    env = {**os.environ, "RAYON_NUM_THREADS": str(threads)}
    done = subprocess.run(
        [str(relief_bin), "simulate", str(scene), "-o", str(out), *map(str, args)],
        capture_output=True, text=True, env=env,
    )
    assert done.returncode == 0, done.stderr


def files_of(json_path):
    """The bytes of a written reference scene: its JSON and its .dat."""
    return json_path.read_bytes(), json_path.with_suffix(".dat").read_bytes()


@pytest.mark.parametrize(
    "kwargs, args",
    [(dict(), []), (dict(rain=0.2, evaporation=0.01, dt=0.3),
                    ["--rain", "0.2", "--evaporation", "0.01", "--dt", "0.3"])],
    ids=["scene-settings", "overrides"],
)
def test_steps_write_the_bytes_relief_simulate_writes(tmp_path, relief_bin, rivers, kwargs,
                                                       args):
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    cli_out, py_out = tmp_path / "cli" / "out.json", tmp_path / "py" / "out.json"
    cli_simulate(relief_bin, rivers, cli_out, "--steps", 6, "--seed", 7, *args)

    scene = relief.open(rivers)
    assert relief.simulate(scene, 4, seed=7, **kwargs) == 4
    assert relief.simulate(scene, 2, seed=7, **kwargs) == 6
    assert scene.info["step"] == 6
    scene.write(py_out)
    assert files_of(py_out) == files_of(cli_out)
    scene.write(tmp_path / "py" / "out.mlhm")
    cli_simulate(relief_bin, rivers, tmp_path / "cli" / "out.mlhm", "--steps", 6, "--seed", 7,
                 *args)
    assert (tmp_path / "py" / "out.mlhm").read_bytes() == (tmp_path / "cli" / "out.mlhm").read_bytes()


def test_the_thread_count_does_not_change_the_steps(tmp_path, relief_bin, rivers):
    (tmp_path / "one").mkdir()
    (tmp_path / "two").mkdir()
    cli_simulate(relief_bin, rivers, tmp_path / "one" / "out.json", "--steps", 5, threads=1)
    cli_simulate(relief_bin, rivers, tmp_path / "two" / "out.json", "--steps", 5, threads=2)
    scene = relief.open(rivers)
    relief.simulate(scene, 5)
    scene.write(tmp_path / "py.json")
    expected = files_of(tmp_path / "one" / "out.json")
    assert files_of(tmp_path / "two" / "out.json") == expected
    assert files_of(tmp_path / "py.json")[1] == expected[1]


def test_the_stepped_scene_renders_as_relief_render_of_the_output(tmp_path, relief_bin,
                                                                   run_relief, rivers):
    Image = pytest.importorskip("PIL.Image")
    out = tmp_path / "out.json"
    cli_simulate(relief_bin, rivers, out, "--steps", 8, "--seed", 3)
    scene = relief.open(rivers)
    before = scene.render(size=(64, 48))
    relief.simulate(scene, 8, seed=3)
    rgb, depth = scene.render(size=(64, 48))
    png, depth_file = tmp_path / "cli.png", tmp_path / "cli.npy"
    run_relief("render", out, "--size", "64x48", "-o", png, "--depth", depth_file)
    assert np.array_equal(rgb, np.asarray(Image.open(png).convert("RGB")))
    assert np.array_equal(depth, np.load(depth_file))
    assert not np.array_equal(depth, before[1]), "the terrain changed"


def test_the_state_reads_as_arrays(tmp_path, relief_bin, rivers):
    scene = relief.open(rivers)
    start = scene.state()
    assert start["step"] == 0 and start["cell_size"] == pytest.approx(256 / 24)
    layers = scene.info["layers"]
    for name in ["bedrock", "sand", "water", "ceiling", "sediment", "damage", "stability"]:
        assert start[name].shape == (layers, 24, 24) and start[name].dtype == np.float32, name
    assert start["fluxes"].shape == (layers, 24, 24, 4) and start["fluxes"].dtype == np.float32
    assert start["layer_counts"].shape == (24, 24) and start["layer_counts"].dtype == np.uint8
    assert np.all(start["water"] == 0)

    relief.simulate(scene, 5, seed=2)
    stepped = scene.state()
    assert stepped["step"] == 5 and stepped["water"].sum() > 0
    assert stepped["sediment"].max() > 0
    out = tmp_path / "out.json"
    cli_simulate(relief_bin, rivers, out, "--steps", 5, "--seed", 2)
    written = relief.open(out).state()
    for name, array in stepped.items():
        assert np.array_equal(array, written[name]), name


def test_simulations_of_two_scenes_run_side_by_side(rivers):
    alone = relief.open(rivers)
    relief.simulate(alone, 4)
    scenes = [relief.open(rivers) for _ in range(3)]
    threads = [threading.Thread(target=relief.simulate, args=(s, 4)) for s in scenes]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for scene in scenes:
        assert np.array_equal(scene.state()["water"], alone.state()["water"])


def test_bad_simulations_raise_relief_errors(tmp_path, relief_bin, run_relief, rivers, terrain):
    np.save(tmp_path / "h.npy", terrain)
    field = relief.open(tmp_path / "h.npy")
    with pytest.raises(relief.ReliefError, match="take MLHM scenes .* this is a 48x40 height field"):
        relief.simulate(field, 1)
    with pytest.raises(relief.ReliefError, match="MLHM scenes"):
        field.state()
    scene = relief.open(rivers)
    for kwargs, cli, message in [
        (dict(steps=0), ["--steps", "0"], "step count '0' is not a whole number between 1 and 10000000"),
        (dict(steps=1, rain=-1), ["--steps", "1", "--rain", "-1"], "water rate -1 is outside 0..100 m/s"),
        (dict(steps=1, dt=20), ["--steps", "1", "--dt", "20"], "time step 20 is outside 0.001..10 s"),
    ]:
        with pytest.raises(relief.ReliefError) as caught:
            relief.simulate(scene, **kwargs)
        assert message in str(caught.value)
        done = run_relief("simulate", rivers, "-o", tmp_path / "o.json", *cli, check=False)
        assert done.returncode != 0 and message in done.stderr, done.stderr
    with pytest.raises(relief.ReliefError, match="written as .json"):
        scene.write(tmp_path / "out.png")
    assert scene.info["step"] == 0
