#!/usr/bin/python3
"""The web dashboard in a real browser: headless Chromium (Debian's chromium and
chromium-driver, driven by python3-selenium) against a real `gaitforge local` running a small
caterpillar study, and against a coordinator that requires tokens.

Checks the study list, the study page's facts, history table, hall of fame with gait
diagrams drawn from the robot's controller, that the fitness curve gains points while the
study runs, a generation's members, the banner for an unknown study; a small real
`gaitforge diagnose` live (its row, stage and progress), then stored (`gaitforge
dashboard`): its verdict, figures, candidates and fits' study links; and the token rules
(401/403/200 over HTTP; the page's token form and ?token=). Saves screenshots, and prints
the time from starting `gaitforge local` to the curve's first point and the page weight of
a first load.

Usage: browser_test.py --bin-dir build/bin --screenshots build/dashboard-screenshots
"""
import argparse
import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

CHROMIUM = "/usr/bin/chromium"
CHROMEDRIVER = "/usr/bin/chromedriver"
INSTALL = "run scripts/install-deps.sh (apt-get install chromium chromium-driver python3-selenium)"
# Never ends by itself within the test: the curve is read while the study runs, then the
# test stops `gaitforge local`.
SPEC = """name: dashboard-browser
seed: 7
engine: ga
population: 8
generations: 100000
objective:
  name: caterpillar.distance
  params: {cycles: 2, settle_cycles: 0}
ga:
  elite: 2
"""
# A small real diagnosis (as tests/e2e/stored_diagnosis_test.cc): the tether-hose case, two
# candidates, short fits; about 20 s on 2 cores.
DIAGNOSIS_SPEC = """name: dashboard-diagnosis
seed: 3
training: [{cases}train/gait-a.csv, {cases}train/gait-b.csv]
held_out: [{cases}held_out/gait-c.csv]
candidates: [tether.constant, ground.slope]
screening_evaluations: 16
full_evaluations: 24
top: 2
try_pairs: false
"""
CASES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "diagnosis", "cases",
                     "tether-hose") + "/"
CLIENT_TOKEN = "client-token-0123456789abcdef"
WORKER_TOKEN = "worker-token-0123456789abcdef"

passed = 0


def check(cond, what):
    global passed
    if not cond:
        raise AssertionError(what)
    passed += 1
    print("ok:", what, flush=True)


def need_browser():
    try:
        import selenium  # noqa: F401
    except ImportError:
        sys.exit(f"FAIL: python3-selenium is missing under /usr/bin/python3: {INSTALL}")
    for path in (CHROMIUM, CHROMEDRIVER):
        if not os.access(path, os.X_OK):
            sys.exit(f"FAIL: {path} is missing: {INSTALL}")


def browser():
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service
    o = webdriver.ChromeOptions()
    o.binary_location = CHROMIUM
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
              "--window-size=1280,1500", "--no-first-run"):
        o.add_argument(a)
    return webdriver.Chrome(service=Service(CHROMEDRIVER), options=o)


def wait(driver, cond, what, timeout=30):
    from selenium.webdriver.support.ui import WebDriverWait
    try:
        return WebDriverWait(driver, timeout, poll_frequency=0.1).until(lambda d: cond(d))
    except Exception as e:
        raise AssertionError(f"timed out after {timeout} s waiting for {what} ({e!r})")


def wait_for(predicate, what, timeout=30):
    until = time.monotonic() + timeout
    while time.monotonic() < until:
        r = predicate()
        if r:
            return r
        time.sleep(0.05)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def css(driver, selector):
    from selenium.webdriver.common.by import By
    return driver.find_elements(By.CSS_SELECTOR, selector)


def texts(driver, selector):
    """The text of every element matching selector, read in one script: the page re-renders
    live, so element handles may go stale between finding and reading them."""
    return driver.execute_script(
        "return Array.from(document.querySelectorAll(arguments[0]), "
        "e => e.innerText ?? e.textContent)",
        selector)


def text_of(driver, selector):
    """The first match's text, or "" (read like texts)."""
    found = texts(driver, selector)
    return found[0] if found else ""


def points(driver):
    e = css(driver, "#curve")
    return int(e[0].get_attribute("data-points")) if e else 0


def page_weight(driver):
    """Bytes transferred for the load: the document and every resource (static files and
    the first API answers), headers included, as the browser's Resource Timing counts them."""
    return driver.execute_script("""
      const nav = performance.getEntriesByType('navigation')[0];
      const res = performance.getEntriesByType('resource');
      const stat = res.filter(r => !r.name.includes('/api/'));
      const sum = (a) => a.reduce((s, r) => s + r.transferSize, 0);
      return {page: nav.transferSize + sum(stat), api: sum(res) - sum(stat),
              files: 1 + stat.length};""")


def start_cli(bin_dir, work, command, text, page):
    """`gaitforge COMMAND TEXT --workers 2` in `work` (the default database,
    runs/gaitforge.db, there) until it prints `dashboard: URL#/PAGE/ID`: (process, URL, ID)."""
    spec = os.path.join(work, command + ".yaml")
    with open(spec, "w") as f:
        f.write(text)
    log_path = os.path.join(work, command + ".log")
    proc = subprocess.Popen(
        [os.path.join(bin_dir, "gaitforge"), command, spec, "--workers", "2", "--out",
         os.path.join(work, "plots")],
        stdout=open(log_path, "w"), stderr=subprocess.STDOUT, cwd=work)

    def url():
        if proc.poll() is not None:
            raise AssertionError(f"gaitforge {command} exited {proc.returncode}: {open(log_path).read()}")
        m = re.search(r"dashboard: (http://\S+/)#/" + page + r"/(\S+)", open(log_path).read())
        return m and (m.group(1), m.group(2))
    base, ident = wait_for(url, f"gaitforge {command} to print the dashboard's URL")
    check(True, f"gaitforge {command} prints the dashboard's URL {base}#/{page}/{ident}")
    return proc, base, ident


def start_local(bin_dir, work):
    started = time.monotonic()
    proc, base, study = start_cli(bin_dir, work, "local", SPEC, "study")
    return proc, started, base, study


def stop(proc, sig=signal.SIGINT):
    if proc.poll() is None:
        proc.send_signal(sig)
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def studies_page(driver, base, study, shots):
    driver.get(base)
    row = f'#studies tr[data-study="{study}"]'
    wait(driver, lambda d: css(d, row), "the study's row in the study list")
    text = text_of(driver, row)
    check("caterpillar.distance" in text and "running" in text,
          f"the study list shows {study} running caterpillar.distance: {text!r}")
    weight = page_weight(driver)
    driver.save_screenshot(os.path.join(shots, "studies.png"))
    css(driver, row)[0].click()
    return weight


def study_page(driver, study, started, shots):
    wait(driver, lambda d: points(d) >= 1, "the fitness curve's first point")
    first_point_s = time.monotonic() - started
    n1 = points(driver)
    facts = text_of(driver, "#facts")
    check("caterpillar" in facts and "running" in facts and "invalid" in facts,
          f"the study's facts name its robot, state and invalid count: {facts!r}")
    wait(driver, lambda d: points(d) > n1, f"the curve to grow beyond {n1} points")
    n2 = points(driver)
    check("running" in text_of(driver, "#facts"),
          f"the curve grew from {n1} to {n2} points while the study runs")
    rows = css(driver, "#history tbody tr")
    check(len(rows) >= n2 - 1, f"the history table has a row per generation ({len(rows)})")
    gait = "#hof .gait svg.diagram[data-kind=phase_onoff] rect.on"
    wait(driver, lambda d: css(d, gait), "a hall-of-fame gait diagram with ON windows")
    labels = texts(driver, "#hof .gait svg.diagram text")
    check("T1" in labels and "B3" in labels and len(texts(driver, "#hof .gait")) == 2,
          "the hall of fame shows its 2 members, each as a gait diagram of actuators T1..B3")
    driver.save_screenshot(os.path.join(shots, "study.png"))
    css(driver, "#history tbody tr")[-1].click()
    wait(driver, lambda d: len(css(d, "#members tbody tr")) == 8, "generation 0's 8 members")
    check(True, "clicking a generation lists its members")
    return first_point_s


def unknown_study(driver, base, shots):
    driver.get(base + "#/study/no-such-study")
    wait(driver, lambda d: css(d, "#banner") and css(d, "#banner")[0].is_displayed(),
         "the error banner for an unknown study")
    text = text_of(driver, "#banner")
    check("no study with id 'no-such-study'" in text, f"an unknown study shows a banner: {text!r}")
    driver.save_screenshot(os.path.join(shots, "unknown-study.png"))


def live_study(driver, bin_dir, work, shots):
    proc, started, base, study = start_local(bin_dir, work)
    try:
        weight = studies_page(driver, base, study, shots)
        first_point_s = study_page(driver, study, started, shots)
        unknown_study(driver, base, shots)
    finally:
        stop(proc)
    return weight, first_point_s, study


def running_diagnosis(driver, bin_dir, work, shots):
    """A diagnosis while it runs: its row in the list, its stage and progress, live."""
    proc, base, diagnosis = start_cli(bin_dir, work, "diagnose",
                                      DIAGNOSIS_SPEC.format(cases=CASES), "diagnosis")
    try:
        driver.get(base + "#/diagnoses")
        row = f'#diagnoses tr[data-diagnosis="{diagnosis}"]'
        wait(driver, lambda d: css(d, row), "the diagnosis's row in the list")
        text = text_of(driver, row)
        check("dashboard-diagnosis" in text and "caterpillar" in text and "running" in text,
              f"the diagnosis list shows {diagnosis} running: {text!r}")
        css(driver, row)[0].click()
        stage = re.compile(r"^[a-z ]+: \d+/\d+ fits done, \d+/\d+ evaluations")
        line = lambda d: text_of(d, "#diagnosis-progress") if css(d, "#diagnosis-progress") else ""
        first = wait(driver, lambda d: stage.match(line(d)) and line(d), "the diagnosis's stage and progress")
        check(True, f"the running diagnosis shows its stage and progress: {first!r}")
        driver.save_screenshot(os.path.join(shots, "diagnosis-running.png"))
        wait(driver, lambda d: line(d) != first, "the progress line to change", timeout=60)
        check(True, f"the progress line updates live: {line(driver)!r}")
        proc.wait(timeout=120)
        check(proc.returncode == 0, f"gaitforge diagnose completes (exit {proc.returncode})")
    finally:
        stop(proc)
    return diagnosis


def figure_loaded(driver, img_id):
    return driver.execute_script(
        "const i = document.getElementById(arguments[0]);"
        "return !!i && i.complete && i.naturalWidth > 0;", img_id)


def stored_diagnosis(driver, base, diagnosis, shots):
    """The completed diagnosis: verdict in words, figures, candidates, fits' study links."""
    driver.get(base + "#/diagnoses")
    row = f'#diagnoses tr[data-diagnosis="{diagnosis}"]'
    wait(driver, lambda d: css(d, row), "the stored diagnosis's row")
    text = text_of(driver, row)
    check("completed" in text and "found" in text, f"the list shows it completed, found: {text!r}")
    css(driver, row)[0].click()
    wait(driver, lambda d: css(d, "#verdict-words") and text_of(d, "#verdict-words"), "the verdict")
    words = text_of(driver, "#verdict-words")
    check(words == "found tether.constant", f"the verdict in words: {words!r}")
    errors = text_of(driver, "#errors")
    check(re.search(r"held-out error \S+ → \S+ mm, training \S+ → \S+ mm", errors),
          f"the errors before and after: {errors!r}")
    params = [e.get_attribute("data-param") for e in css(driver, '#effects [data-effect="tether.constant"] tr[data-param]')]
    check(any(p.startswith("effect.") for p in params), f"the named effect's fitted parameters: {params}")
    for img in ("located-figure", "diagnosis-figure"):
        wait(driver, lambda d: figure_loaded(d, img), f"the figure {img} to load")
    check(True, "both figures load as images (naturalWidth > 0): located.svg, diagnosis.svg")
    cand = css(driver, '#candidates tr[data-candidate="ground.slope"]')
    why = cand[0].find_element("css selector", "td.why").text if cand else ""
    check(why, f"the candidates table has ground.slope with why not: {why!r}")
    screened = [e.get_attribute("data-candidate") for e in css(driver, "#screening tr[data-candidate]")]
    check(sorted(screened) == ["ground.slope", "tether.constant"], f"the screening lists both: {screened}")
    check(css(driver, "#corrected-model"), "the corrected model is linked")
    driver.save_screenshot(os.path.join(shots, "diagnosis.png"))
    driver.execute_script("document.getElementById('figures').scrollIntoView()")
    driver.save_screenshot(os.path.join(shots, "diagnosis-figures.png"))
    cand[0].find_element("css selector", "a.study").click()
    wait(driver, lambda d: css(d, "#facts") and "completed" in text_of(d, "#facts"),
         "the fit's study page")
    check(True, "a candidate's fit opens its study page")


def dashboard_command(driver, bin_dir, work, study, diagnosis, shots):
    """`gaitforge dashboard` serves the database the study and the diagnosis left until it
    is stopped."""
    proc = subprocess.Popen([os.path.join(bin_dir, "gaitforge"), "dashboard"], cwd=work,
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        base = proc.stdout.readline().strip()
        check(base.startswith("http://127.0.0.1:"), f"gaitforge dashboard prints its URL {base!r}")
        code, body = http_status(base + "api/studies/" + study + "/history?since=1")
        gens = json.loads(body)["generations"] if code == 200 else []
        check(gens and gens[0]["generation"] == 1,
              f"it serves the stored study: {len(gens)} generations since 1")
        stored_diagnosis(driver, base, diagnosis, shots)
    finally:
        stop(proc)
    check(proc.returncode == 0, f"Ctrl-C stops gaitforge dashboard (exit {proc.returncode})")


def http_status(url, token=None):
    req = urllib.request.Request(url, headers={"Authorization": "Bearer " + token} if token else {})
    try:
        with urllib.request.urlopen(req, timeout=10) as r:
            return r.status, r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.read().decode()


def start_coordinator_with_tokens(bin_dir, work):
    port_file = os.path.join(work, "port")
    env = dict(os.environ, GAITFORGE_CLIENT_TOKEN=CLIENT_TOKEN, GAITFORGE_WORKER_TOKEN=WORKER_TOKEN)
    proc = subprocess.Popen(
        [os.path.join(bin_dir, "gaitforge-coordinator"), "--listen", "127.0.0.1:0",
         "--db", os.path.join(work, "tokens.db"), "--port-file", port_file,
         "--dashboard-listen", "127.0.0.1:0", "--log-level", "warn"], env=env)

    def url():
        if proc.poll() is not None:
            raise AssertionError(f"gaitforge-coordinator exited {proc.returncode}")
        if not os.path.exists(port_file):
            return None
        m = re.search(r"^dashboard (\S+)$", open(port_file).read(), re.M)
        return m and m.group(1)
    return proc, wait_for(url, "the coordinator's dashboard URL in its port file")


def tokens(driver, bin_dir, work, shots):
    proc, base = start_coordinator_with_tokens(bin_dir, work)
    try:
        code, body = http_status(base + "api/studies")
        check(code == 401 and "missing 'authorization: Bearer TOKEN' header" in body,
              f"no token: 401 {body}")
        code, body = http_status(base + "api/studies", WORKER_TOKEN)
        check(code == 403 and "worker token cannot" in body, f"a worker token: 403 {body}")
        code, body = http_status(base + "api/studies", CLIENT_TOKEN)
        check(code == 200 and json.loads(body) == {"studies": []}, "the client token: 200")
        codes = [http_status(base + "api/diagnoses", t)[0] for t in (None, WORKER_TOKEN, CLIENT_TOKEN)]
        check(codes == [401, 403, 200], f"/api/diagnoses: the same tokens ({codes})")
        check(http_status(base)[0] == 200, "the page itself (no data) loads without a token")
        driver.get(base)
        wait(driver, lambda d: css(d, "#auth")[0].is_displayed(), "the token form")
        check("refused" in text_of(driver, "#banner"), "the page says the token was refused")
        driver.save_screenshot(os.path.join(shots, "token-form.png"))
        css(driver, "#token")[0].send_keys(CLIENT_TOKEN + "\n")
        wait(driver, lambda d: "No study yet" in text_of(d, "#studies"),
             "the study list after entering the token")
        check(not css(driver, "#banner")[0].is_displayed(), "with the token the banner is gone")
        driver.delete_all_cookies()
        driver.execute_script("sessionStorage.clear()")
        driver.get(base + "?token=" + CLIENT_TOKEN)
        wait(driver, lambda d: "No study yet" in text_of(d, "#studies"), "the list with ?token=")
        check("token" not in driver.current_url, f"?token= is taken off the address: {driver.current_url}")
    finally:
        stop(proc, signal.SIGTERM)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin-dir", required=True)
    ap.add_argument("--screenshots", required=True)
    a = ap.parse_args()
    a.bin_dir = os.path.abspath(a.bin_dir)
    need_browser()
    os.makedirs(a.screenshots, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="gaitforge-dashboard-") as work:
        driver = browser()
        try:
            weight, first_point_s, study = live_study(driver, a.bin_dir, work, a.screenshots)
            diagnosis = running_diagnosis(driver, a.bin_dir, work, a.screenshots)
            dashboard_command(driver, a.bin_dir, work, study, diagnosis, a.screenshots)
            tokens(driver, a.bin_dir, work, a.screenshots)
        except Exception:
            driver.save_screenshot(os.path.join(a.screenshots, "failure.png"))
            raise
        finally:
            driver.quit()
    print(f"measured: first curve point {first_point_s:.2f} s after starting gaitforge local; "
          f"first load {weight['page']} bytes in {weight['files']} files "
          f"(+ {weight['api']} bytes of API answers); screenshots in {a.screenshots}")
    print(f"{passed} passed, 0 failed")


if __name__ == "__main__":
    main()
