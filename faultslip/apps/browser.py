"""Driving the classroom app in a real browser: headless Chromium through Selenium (tests and benchmark).

The app's widgets and data sources carry names, so a script reaches them through BokehJS's document
(``Bokeh.documents[0].get_model_by_name``): setting a knob there is what dragging it does, a change the
page sends to the server, whose callback recomputes and sends the new data back.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

import faultslip

CHROMIUM = ("/usr/bin/chromium", "/usr/bin/chromium-browser", "/usr/bin/google-chrome")
CHROMEDRIVER = ("/usr/bin/chromedriver",)


def missing() -> str | None:
    """Why no browser test can run here, or None."""
    try:
        import selenium  # noqa: F401  heavy: optional, the browser tests' driver
    except ImportError:
        return "selenium is not installed (pip install 'faultslip[app]')"
    if not any(os.path.exists(path) for path in CHROMIUM):
        return "no Chromium (Debian: apt-get install chromium chromium-driver)"
    if not any(os.path.exists(path) for path in CHROMEDRIVER) and not shutil.which("chromedriver"):
        return "no chromedriver (Debian: apt-get install chromium-driver)"
    return None


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


@contextmanager
def running_app(timeout: float = 60.0):
    """``faultslip classroom`` as a child process on a free port; yields its address; stops it after."""
    port = free_port()
    # the child imports the faultslip this process runs (a checkout beside an installed copy has no compiled
    # extensions, and the chain's catalogue, chaotic, then differs): its package's folder first on the path, and
    # a working folder that holds no other copy
    package_root = str(Path(faultslip.__file__).resolve().parent.parent)
    environment = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [package_root,
                                                                          os.environ.get("PYTHONPATH")])))
    process = subprocess.Popen([sys.executable, "-m", "faultslip.cli", "classroom", "--port", str(port)],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=environment,
                               cwd=tempfile.gettempdir())
    try:
        deadline = time.monotonic() + timeout
        line = ""
        while time.monotonic() < deadline:
            line = process.stdout.readline()
            if "http://" in line or process.poll() is not None:
                break
        if "http://" not in line:
            raise RuntimeError(f"faultslip classroom did not start: {line.strip()!r}")
        yield line[line.index("http://"):].split()[0]
    finally:
        process.terminate()
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()


@contextmanager
def chromium(width: int = 1400, height: int = 1000):
    """Headless Chromium (the system's) with the flags a closed network needs."""
    from selenium import webdriver  # heavy: optional, the browser tests' driver
    from selenium.webdriver.chrome.service import Service  # heavy: as above

    options = webdriver.ChromeOptions()
    options.binary_location = next(path for path in CHROMIUM if os.path.exists(path))
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--disable-quic",
                 "--no-first-run", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", f"--window-size={width},{height}"):
        options.add_argument(flag)
    driver_path = next((path for path in CHROMEDRIVER if os.path.exists(path)), None) or shutil.which("chromedriver")
    driver = webdriver.Chrome(service=Service(driver_path), options=options)
    try:
        yield driver
    finally:
        driver.quit()


def wait_for(driver, script: str, timeout: float = 30.0, poll: float = 0.05):
    """Run ``script`` (a JS expression's body that returns) until it returns something truthy."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = driver.execute_script(script)
        if value:
            return value
        time.sleep(poll)
    raise TimeoutError(f"the page did not reach the state in {timeout:g} s: {script}")


READY = """if (!(window.Bokeh && Bokeh.documents.length)) { return false; }
const m = Bokeh.documents[0].get_model_by_name('lab_status'); return !!(m && m.text.length);"""


def open_app(driver, url: str) -> None:
    driver.get(url)
    wait_for(driver, READY)


def model_value(driver, name: str, attribute: str):
    return driver.execute_script(f"return Bokeh.documents[0].get_model_by_name({name!r}).{attribute};")


def set_knob(driver, name: str, value) -> None:
    """Set a widget the way a drag does: its value, then the throttled value the server listens to."""
    driver.execute_script(f"""const m = Bokeh.documents[0].get_model_by_name({name!r});
        m.value = {value!r}; if ('value_throttled' in m) {{ m.value_throttled = {value!r}; }}""")


def column(driver, source: str, key: str) -> list:
    """A data source's column as the page holds it."""
    return driver.execute_script(f"""const d = Bokeh.documents[0].get_model_by_name({source!r}).data;
        const c = (d instanceof Map) ? d.get({key!r}) : d[{key!r}]; return Array.from(c);""")
