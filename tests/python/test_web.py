"""macsim_web in a real browser (ctest label `browser`): macsim on the demo world, macsim_web,
and Debian's headless Chromium driven with Selenium through chromedriver
(tools/python/headless_chromium.py). The page must draw every object of the world state, show a
picture that is not blank, and follow the robot when it drives; bad requests get errors and the
server keeps serving; a controller's plan is listed beside the view as it acts, with a label over
each thing it judged."""

import os
import re
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import pytest

import headless_chromium
import macsim
from conftest import binary, held_domain, source, spawning, start_macsim


def wait_until(check, timeout, what):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = check()
        if value:
            return value
        time.sleep(0.2)
    raise AssertionError(f"{what} within {timeout} s")


@pytest.fixture(scope="module")
def chromium():
    """One headless Chromium for the file's tests (a start costs seconds of CPU)."""
    browser = headless_chromium.start()
    try:
        yield browser
    finally:
        browser.quit()


@pytest.fixture(scope="module")
def served_domain():
    """The DDS domain of the simulator the first two tests share."""
    with held_domain() as number:
        yield number


@pytest.fixture(scope="module")
def served(served_domain, chromium):
    """macsim on the demo world and macsim_web serving it, shared by the first two tests (the
    second only reads: it asks for pages and sends malformed messages)."""
    with spawning() as spawn:
        start_macsim(spawn, served_domain, "worlds/DemoWorld_v1.xml", "--cameras", "320x240")
        web = spawn([binary("macsim_web"), "--domain", served_domain, "--port", "0"])
        assert web.wait_for_output("serving http://", 20), web.output()
        url = re.search(r"serving (http://\S+)", web.output()).group(1)
        yield url, chromium, web


def page_view(browser):
    """What the page shows (window.macsimView), or None before it is set up."""
    return browser.execute_script("return window.macsimView || null;")


def test_the_page_lists_a_controllers_plan_as_it_acts_and_labels_what_it_judged(domain, spawn,
                                                                               chromium):
    # kurt_plan on the open-door family's layout 5 against a lock-step simulator: a plan of two
    # steps (go to the door, drive through), the cans it saw judged. First in the file: the
    # simulator the next two tests share (running in real time) starts after it.
    start_macsim(spawn, domain, "worlds/goals/door_open.xml", "--seed", "5", "--lockstep")
    web = spawn([binary("macsim_web"), "--domain", domain, "--port", "0"])
    assert web.wait_for_output("serving http://", 20), web.output()
    url = re.search(r"serving (http://\S+)", web.output()).group(1)
    browser = chromium
    browser.get(url)
    # In lock-step nothing is published before a controller steps the simulation.
    wait_until(lambda: (v := page_view(browser)) and v["connected"], 30, "no connection")
    assert page_view(browser)["plan"] is None  # no controller yet
    plan = spawn([binary("kurt_plan"), "--domain", domain, "--lockstep", "--pddl-domain",
                  source("affordances/domains/kurt3d_room_by_hand.pddl")])
    under_way = wait_until(lambda: (v := page_view(browser)) and v["plan"] and v["plan"]["current"] >= 0
                           and v["plan"], 120, "no step under way on the page")
    assert under_way["steps"][under_way["current"]][1] == "under way"
    assert page_view(browser)["drawn"] > 0
    assert plan.wait(120) == 0, plan.output()
    shown = wait_until(lambda: (v := page_view(browser)) and v["plan"] and v["plan"]["outcome"]
                       and v["plan"], 20, "the plan's outcome did not reach the page")
    assert shown["outcome"].startswith("goal reached: yes, plan steps: 2"), shown
    assert shown["goal"] == "through-door" and shown["round"] == 1
    assert shown["steps"] == [["(go start door)", "as predicted"], ["(drive-through door)", "as predicted"]]
    for action, _ in shown["steps"]:
        assert action + ": as predicted" in plan.output()
    # Beside the view, the steps as listed items; over the view, a label per judged thing.
    items = browser.execute_script(
        "return [...document.querySelectorAll('#plan li')].map(e => e.textContent);")
    assert len(items) == 2 and items[1].startswith("(drive-through door) -> (beyond door)"), items
    assert len(shown["labels"]) >= 1, shown
    for name in shown["labels"]:
        assert re.fullmatch(r"[a-z]+_[0-9]+", name), name


def test_the_page_draws_the_world_and_follows_the_robot(served, served_domain):
    url, browser, web = served
    participant = macsim.Participant(domain=served_domain, name="web_test")
    world = macsim.WorldState(participant)
    objects = world.wait(lambda o: len(o) > 20, timeout=30)
    browser.get(url)
    view = wait_until(lambda: (v := page_view(browser)) and v["drawn"] == len(objects) and v, 60,
                      f"the page did not draw the world's {len(objects)} objects")
    assert view["objectIds"] == sorted(objects)
    assert view["domain"] == served_domain and view["connected"]
    assert "objects drawn" in browser.execute_script("return document.title;")
    names = browser.execute_script(
        "return [...document.querySelectorAll('#objects li')].map(e => e.textContent);")
    assert sorted(names) == sorted(f"{i} {o.name}" for i, o in objects.items())

    png = browser.get_screenshot_as_png()
    picture = headless_chromium.decode_png(png)
    out = Path(os.environ.get("MACSIM_BIN_DIR", ".")).parent / "web_test_screenshot.png"
    out.write_bytes(png)
    assert picture.shape[0] >= 600 and picture.std() > 20, "a blank picture"
    assert len(np.unique(picture.reshape(-1, 3)[::7], axis=0)) > 200, "too few colours"

    # Sensors reach the page: a scan, and camera images.
    wait_until(lambda: page_view(browser)["scans"] > 0, 20, "no laser scan on the page")
    wait_until(lambda: page_view(browser)["images"] >= 2, 20, "no camera image on the page")

    # The robot drives; the page's pose follows the simulator's.
    robot = macsim.Robot(participant)
    start = wait_until(lambda: page_view(browser)["robotPose"], 20, "no robot pose on the page")
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        robot.cmd_vel(0.3, 0.0)
        pose = page_view(browser)["robotPose"]
        if np.hypot(pose[0] - start[0], pose[1] - start[1]) > 0.4:
            break
        time.sleep(0.1)
    robot.stop()
    pose = page_view(browser)["robotPose"]
    assert np.hypot(pose[0] - start[0], pose[1] - start[1]) > 0.4, (start, pose)

    # Camera modes are buttons with the simulator's names.
    for mode in ("MouseOnly", "FixedFollow", "Follow", "Inside", "LeftCamera", "RightCamera"):
        browser.execute_script(f"document.querySelector('button[data-mode={mode}]').click();")
        assert page_view(browser)["mode"] == mode


def test_bad_requests_get_errors_and_the_server_keeps_serving(served):
    url, browser, web = served
    with pytest.raises(urllib.error.HTTPError) as error:
        urllib.request.urlopen(url + "no/such/page.html", timeout=10)
    assert error.value.code == 404
    with pytest.raises(urllib.error.HTTPError) as error:
        urllib.request.urlopen(url + "../../etc/passwd", timeout=10)
    assert error.value.code == 404
    browser.get(url)
    wait_until(lambda: page_view(browser) and page_view(browser)["connected"], 30, "no connection")
    # Malformed messages over a WebSocket of the browser's: each gets an error, in order.
    replies = browser.execute_async_script("""
        const done = arguments[arguments.length - 1];
        const socket = new WebSocket(`ws://${location.host}/ws`);
        const errors = [];
        socket.onmessage = (e) => {
          const m = JSON.parse(e.data);
          if (m.type === 'error' || m.type === 'hello') errors.push(m);
          if (errors.length === 4) { socket.close(); done(errors); }
        };
        socket.onopen = () => {
          socket.send('not json {');
          socket.send('[1, 2]');
          socket.send(JSON.stringify({type: 'explode'}));
          socket.send(JSON.stringify({type: 'hello'}));
        };""")
    assert [r["type"] for r in replies] == ["error", "error", "error", "hello"]
    assert "not JSON" in replies[0]["message"] and "explode" in replies[2]["message"]
    # Browsers come and go; their connections are freed, the server still serves.
    for _ in range(3):
        browser.get("about:blank")
        browser.get(url)
    wait_until(lambda: page_view(browser) and page_view(browser)["drawn"] > 0, 30,
               "the page after reloads")
    with urllib.request.urlopen(url, timeout=10) as page:
        assert b"macsim_web" in page.read()
