"""Debian's Chromium, headless, driven with Selenium (python3-selenium) through Debian's
chromedriver, and its screenshots decoded with PIL (python3-pil): what macsim_web's browser test
and benchmark drive the page with. chromedriver's path is given, so Selenium never looks for a
driver of its own (selenium-manager) and nothing is fetched."""

import io

import numpy as np
from PIL import Image
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

CHROMEDRIVER = "/usr/bin/chromedriver"
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = ["--headless=new", "--no-sandbox", "--enable-unsafe-swiftshader",
                 "--use-angle=swiftshader", "--window-size=1024,768", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--disable-dev-shm-usage"]


def start(chromedriver=CHROMEDRIVER, chromium=CHROMIUM):
    """A new browser: its own chromedriver on a free port of this machine and one session.
    quit() ends both."""
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for argument in CHROMIUM_ARGS:
        options.add_argument(argument)
    return webdriver.Chrome(service=Service(executable_path=chromedriver), options=options)


def decode_png(data):
    """A PNG (a screenshot: browser.get_screenshot_as_png()) as an H x W x 3 array of 8-bit
    RGB."""
    with Image.open(io.BytesIO(data)) as picture:
        return np.asarray(picture.convert("RGB"))
