"""render_many on a Dask LocalCluster with two worker processes, including a worker killed
in the middle of a batch (the scheduler reschedules its chunks: nothing lost, no duplicate
frame)."""

from __future__ import annotations

import os
import signal

import distributed  # requirements-dev.txt installs it (the [dask] extra)
import numpy as np
import pytest
import shadelab_rs as sl
from PIL import Image
from shadelab_rs.distributed import render_many

KW = dict(width=160, height=120, threads=1)


@pytest.fixture(scope="module")
def client():
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as c,
    ):
        yield c


@pytest.fixture(scope="module")
def scene_cams() -> tuple[sl.Scene, list[sl.Camera]]:
    scene, _ = sl.demo_scene()
    cams = [
        sl.Camera.look_at((4 * np.sin(a), 1.2, 4 * np.cos(a)), (0, -0.1, 0), fov_y=40)
        for a in np.linspace(0, 2 * np.pi, 24, endpoint=False)
    ]
    return scene, cams


def test_dask_matches_render_batch(client, scene_cams):
    scene, cams = scene_cams
    want, depth = sl.render_batch(scene, cams, return_depth=True, **KW)
    got, got_depth = render_many(scene, cams, client, chunk_size=5, return_depth=True, **KW)
    assert got.tobytes() == want.tobytes()
    assert got_depth.tobytes() == depth.tobytes()


def test_worker_killed_mid_batch(client, scene_cams, tmp_path):
    scene, cams = scene_cams
    before = client.run(os.getpid)
    killed: list[int] = []

    def progress(done, total):
        if not killed and done < total:  # the first chunk is back: kill a worker now
            pid = next(iter(before.values()))
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    paths = render_many(
        scene, cams, client, chunk_size=1, output_dir=tmp_path, progress=progress, **KW
    )
    assert killed
    want = sl.render_batch(scene, cams, **KW)
    assert sorted(os.listdir(tmp_path)) == [p.name for p in paths]  # no duplicate, no temporary
    for i, p in enumerate(paths):
        assert np.asarray(Image.open(p)).tobytes() == want[i].tobytes(), i
    # The nanny started a new worker in place of the killed one.
    client.wait_for_workers(2, timeout=60)
    assert killed[0] not in client.run(os.getpid).values()
