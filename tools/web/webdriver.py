"""A small WebDriver client for Debian's Chromium through chromedriver (plain HTTP and JSON, the
standard library only), and a PNG decoder for its screenshots: what macsim_web's browser test
and benchmark drive the page with."""

import base64
import json
import os
import signal
import struct
import subprocess
import tempfile
import time
import urllib.request
import zlib

import numpy as np

CHROMIUM_ARGS = ["--headless=new", "--no-sandbox", "--enable-unsafe-swiftshader",
                 "--use-angle=swiftshader", "--window-size=1024,768", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--disable-dev-shm-usage"]


def decode_png(data):
    """An 8-bit RGB or RGBA PNG as an H x W x C array (zlib and the five row filters)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    pos, idat = 8, b""
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color = struct.unpack(">IIBB", body[:10])
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    assert depth == 8 and color in (2, 6)
    channels = 3 if color == 2 else 4
    raw = np.frombuffer(zlib.decompress(idat), np.uint8).reshape(height, 1 + width * channels)
    out = np.zeros((height, width * channels), np.int32)
    previous = np.zeros(width * channels, np.int32)
    for y in range(height):
        kind, row = raw[y, 0], raw[y, 1:].astype(np.int32)
        if kind == 0:
            line = row
        elif kind == 2:
            line = (row + previous) & 255
        else:
            line = np.zeros_like(row)
            for x in range(len(row)):
                left = line[x - channels] if x >= channels else 0
                up = previous[x]
                corner = previous[x - channels] if x >= channels else 0
                if kind == 1:
                    predictor = left
                elif kind == 3:
                    predictor = (left + up) // 2
                else:
                    p = left + up - corner
                    pa, pb, pc = abs(p - left), abs(p - up), abs(p - corner)
                    predictor = left if pa <= pb and pa <= pc else up if pb <= pc else corner
                line[x] = (row[x] + predictor) & 255
        out[y] = line
        previous = line
    return out.reshape(height, width, channels)[:, :, :3].astype(np.uint8)


class Browser:
    """One headless Chromium session through chromedriver's WebDriver interface."""

    def __init__(self, port):
        self.base = f"http://127.0.0.1:{port}"
        caps = {"capabilities": {"alwaysMatch": {"browserName": "chrome", "goog:chromeOptions": {
            "binary": "/usr/bin/chromium", "args": CHROMIUM_ARGS}}}}
        self.session = self.call("POST", "/session", caps)["sessionId"]

    def call(self, method, path, body=None):
        request = urllib.request.Request(
            self.base + path, method=method, headers={"Content-Type": "application/json"},
            data=None if body is None else json.dumps(body).encode())
        with urllib.request.urlopen(request, timeout=60) as reply:
            return json.loads(reply.read())["value"]

    def open(self, url):
        self.call("POST", f"/session/{self.session}/url", {"url": url})

    def run(self, script, *args):
        return self.call("POST", f"/session/{self.session}/execute/sync",
                         {"script": script, "args": list(args)})

    def view(self):
        return self.run("return window.macsimView || null;")

    def screenshot(self):
        return base64.b64decode(self.call("GET", f"/session/{self.session}/screenshot"))

    def quit(self):
        self.call("DELETE", f"/session/{self.session}")




class ChromeDriver:
    """chromedriver on a port of this machine, stopped and reaped by stop()."""

    def __init__(self, port, binary="/usr/bin/chromedriver"):
        self.port = port
        self.log = tempfile.TemporaryFile()
        self.process = subprocess.Popen([binary, f"--port={port}"], stdout=self.log,
                                        stderr=subprocess.STDOUT, start_new_session=True)
        deadline = time.monotonic() + 20
        while b"started successfully" not in self.output():
            if self.process.poll() is not None or time.monotonic() > deadline:
                self.stop()
                raise RuntimeError("chromedriver did not start")
            time.sleep(0.05)

    def output(self):
        self.log.seek(0)
        return self.log.read()

    def browser(self):
        return Browser(self.port)

    def stop(self):
        if self.process.poll() is None:
            os.killpg(self.process.pid, signal.SIGTERM)
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                os.killpg(self.process.pid, signal.SIGKILL)
                self.process.wait()
