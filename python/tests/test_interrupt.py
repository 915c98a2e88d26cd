"""Ctrl-C stops every long call (issue 56): a timer thread sends SIGINT while the call runs,
and the call raises KeyboardInterrupt instead of running to its end (before, the signal
was seen only when the call returned: 17.6 s into ``rhonn.fit``). How soon is measured and
printed, not asserted (speed belongs in benches); that the call was interrupted at all is
asserted: without the check it completes and returns."""

import os
import signal
import threading
import time

import numpy as np
import pytest

import rhonn


def _interrupt_after(seconds):
    sent = {}

    def fire():
        sent["at"] = time.perf_counter()
        os.kill(os.getpid(), signal.SIGINT)

    t = threading.Timer(seconds, fire)
    t.start()
    return sent, t


def _interrupted(call):
    # Python turns SIGINT into KeyboardInterrupt only when its parent left the signal at
    # its default; a job started in the background by a non-interactive shell (`nohup ...
    # &`) inherits it ignored, and the call then runs to its end. Ctrl-C's own handler,
    # set here for the call, is what a user at a terminal has.
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    sent, timer = _interrupt_after(0.5)
    start = time.perf_counter()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    end = time.perf_counter()
    assert "at" in sent, "the call ended before the signal was sent"
    return end - sent["at"], end - start


def test_ctrl_c_interrupts_a_fit_a_campaign_and_a_run(tanks, tmp_path):
    est, _ = tanks
    # The default selection on ten copies of the tanks: far longer than the half second.
    u = [est["u"]] * 10
    y = [est["y"]] * 10
    latency, _ = _interrupted(lambda: rhonn.fit(u, y, dt=4.0))
    print(f"rhonn.fit: KeyboardInterrupt {latency:.3f} s after SIGINT")
    latency, _ = _interrupted(lambda: rhonn.campaign("tanks-identify", runs=1_000_000, out=tmp_path / "c"))
    print(f"rhonn.campaign: KeyboardInterrupt {latency:.3f} s after SIGINT")
    # The calls after an interrupt run as usual (the stop request is forgotten).
    m = rhonn.fit(est["u"], est["y"], dt=4.0, model={"kind": "arx", "na": 2, "nb": 2})
    assert np.isfinite(m.score(est["u"], est["y"])[0]["rms_error"])
    table = rhonn.campaign("tanks-identify", runs=3, out=tmp_path / "c2")
    assert len(table["run"]) == 3
