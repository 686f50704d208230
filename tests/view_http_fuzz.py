#!/usr/bin/env python3
"""A bounded fuzz run of `svr view`'s HTTP surface (issue 41), on loopback only.

Starts `svr view` on a small scene of its own (a procedural sphere, the rgb model, raycast) with
an access token, then sends random requests over raw sockets to 127.0.0.1: random methods and
paths (the API's, the page's, traversal, junk), queries (known and unknown parameters; numbers
huge, negative, NaN, percent-encoded, binary; the token right, wrong or missing), headers
(Host own, foreign, missing, repeated, empty; Origin own, foreign, null; Cookie with the right
token, a wrong one, another port's, garbage; Content-Length right, short, long, negative, not a
number, repeated; Transfer-Encoding chunked with good and broken chunks, or unknown codings) and
bodies (mix JSON, mutated JSON, binary). Every so often a plain request checks that the server
still answers.

Passes when: the server never dies; no answer is 5xx but a render that fails (500, its reason
in the body, from /api/render) or 503 (out of memory for that request); the server still answers
at the end; its resident memory grows by at most --max-growth-mib over the run, and by at most
a quarter of that over the second half (memory is held, not leaked); it stops on SIGINT with
exit 0 and no sanitizer report. Prints the run's figures (requests, seconds, answers by status,
memory) as one JSON line.

Usage: view_http_fuzz.py SVR [--requests N] [--seconds S] [--seed K] [--max-growth-mib M]
"""
import argparse
import collections
import json
import os
import random
import re
import signal
import socket
import subprocess
import sys
import tempfile
import time

SCENE = {
    "volume": {"procedural": "sphere", "size": 24},
    "materials": {"red": {"reflectance": "ColorChecker/red", "opacity": 0.6},
                  "blue": {"reflectance": "ColorChecker/blue", "opacity": 0.6}},
    "transfer_function": {"type": "scalar", "points": [[0.2, "red"], [0.8, "blue"]],
                          "opacity": [[0.0, 0.0], [0.2, 1.0]]},
    "lights": [{"name": "D65", "library": "D65"}, {"name": "A", "library": "A"}],
    "light_mixes": {"half": {"D65": 0.5, "A": 0.5}},
    "image": {"width": 32, "height": 32},
    "model": "rgb",
}
TOKEN = "fuzz-token-0123456789"
PATHS = ["/", "/index.html", "/viewer.js", "/mixer.js", "/relighter.js", "/viewer.css",
         "/api/scene", "/api/light", "/api/mixer-weights", "/api/render", "/api/mixes",
         "/api/nothing", "/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/api/render/",
         "//api/scene", "/api/%00", "/\u00e9", "/" + "a" * 300, "*", "http://127.0.0.1/api/scene"]
PARAMS = ["azimuth", "elevation", "zoom", "width", "height", "samples", "name", "x", "y", "nodes",
          "relight", "token", "colour", ""]
VALUES = ["0", "1", "-1", "8", "16", "32", "2048", "2049", "1e400", "nan", "inf", "-inf", "1.5",
          "abc", "", "%00", "%ff%fe", "half", "float", "double", "D65", "F11", "NoSuch", "dusk",
          "../evil", "js", "webgl2", "0:0:1,1:0:0", "0:0", "1e6:1:1", TOKEN, "wrong-token",
          "9" * 40, "%25", "a%20b", "\u2603"]


# Requests the server should answer 2xx, for the half of the run that starts from one of them.
def valid_request(rng: random.Random) -> tuple:
    size = lambda: str(rng.choice([1, 8, 16, 33, 64, 128]))  # noqa: E731
    return rng.choice([
        ("GET", "/", [f"relight={rng.choice(['js', 'webgl2', 'auto'])}"]),
        ("GET", rng.choice(PATHS[2:6]), []),
        ("GET", "/api/scene", []),
        ("GET", "/api/light", [f"name={rng.choice(['D65', 'F11', 'LED-B3', 'ColorChecker/red'])}"]),
        ("GET", "/api/mixer-weights", [f"x={rng.uniform(-2, 2):.3f}", f"y={rng.uniform(-2, 2):.3f}"]),
        ("GET", "/api/render", [f"width={size()}", f"height={size()}", f"azimuth={rng.uniform(-400, 400):.1f}",
                                f"elevation={rng.uniform(-90, 90):.1f}", f"zoom={rng.uniform(0.1, 5):.2f}"]),
        ("POST", "/api/mixes", [f"name=m{rng.randrange(20)}"]),
    ])


def request(rng: random.Random, port: int) -> tuple:
    """One random request: its bytes, its method and path (for judging the answer), and whether
    its framing promises more body than it sends."""
    faults = 0 if rng.random() < 0.3 else rng.choice([1, 1, 2, 3, 8])
    fault = lambda: faults > 0 and rng.random() < min(1.0, faults / 4)  # noqa: E731
    method, path, query = valid_request(rng)
    if fault():
        method = rng.choice(["GET", "POST", "HEAD", "PUT", "DELETE", "OPTIONS", "PATCH", "G\u00c9T", "", "GET GET"])
    if fault():
        path = rng.choice(PATHS)
    if fault():
        query = [f"{rng.choice(PARAMS)}={rng.choice(VALUES)}" for _ in range(rng.choice([1, 2, 3, 6]))]
    if not fault():
        query.append(f"token={TOKEN}")
    elif rng.random() < 0.5:
        query.append("token=" + rng.choice(VALUES))
    target = path + ("?" + "&".join(query) if query else "")
    own = f"127.0.0.1:{port}"
    headers = []
    host = own if not fault() else rng.choice([f"localhost:{port}", f"[::1]:{port}", "attacker.example",
                                                f"attacker.example:{port}", "", "127.0.0.1", None, "dup"])
    if host == "dup":
        headers += [("Host", own), ("Host", "attacker.example")]
    elif host is not None:
        headers.append(("Host", host))
    origin = rng.choice([None, f"http://{own}"]) if not fault() else rng.choice(
        ["http://attacker.example", "null", "", f"https://{own}", "http://" + "x" * 200])
    if origin is not None:
        headers.append(("Origin", origin))
    cookie = rng.choice([None, f"svr-token-{port}={TOKEN}"]) if not fault() else rng.choice(
        [f"svr-token-{port + 1}={TOKEN}", f"svr-token-{port}=nope", "a=b; c", ";;;=", "x" * 5000])
    if cookie is not None:
        headers.append(("Cookie", cookie))
    body = b""
    if method == "POST" or fault():
        body = b'{"weights": {"D65": 0.25, "F11": 0.75}}' if not fault() else rng.choice([
            json.dumps({"weights": {rng.choice(["D65", "A", "F11", "Nope"]): rng.choice([0, 1, 0.5, -1, 1e308])}}).encode(),
            b"not json", b"{" * 200, b"", bytes(rng.randrange(256) for _ in range(rng.randrange(1, 300))),
            b'{"weights": ' + b'[' * 100 + b'}', b" " * 70000])
        headers.append(("Content-Type", "application/json" if not fault() else rng.choice(
            ["text/plain", "application/x-www-form-urlencoded", ""])))
    framing = "length" if not fault() else rng.choice(
        ["short", "long", "negative", "junk", "twice", "chunked", "bad-chunk", "gzip", "none"])
    if framing == "length" or (framing == "none" and body):
        headers.append(("Content-Length", str(len(body))))
    elif framing == "short":
        headers.append(("Content-Length", str(max(0, len(body) - 3))))
    elif framing == "long":
        headers.append(("Content-Length", str(len(body) + 10)))
    elif framing == "negative":
        headers.append(("Content-Length", "-5"))
    elif framing == "junk":
        headers.append(("Content-Length", rng.choice(["abc", "1e3", "99999999999999999999", " 4"])))
    elif framing == "twice":
        headers += [("Content-Length", str(len(body))), ("Content-Length", "0")]
    elif framing in ("chunked", "bad-chunk"):
        headers.append(("Transfer-Encoding", "chunked"))
        body = (b"%x\r\n" % len(body) + body + b"\r\n0\r\n\r\n") if framing == "chunked" \
            else rng.choice([b"zz\r\nabc\r\n0\r\n\r\n", b"ffffffffffffffff\r\nab", b"3\r\nabcdef", b"-1\r\n\r\n"])
    elif framing == "gzip":
        headers += [("Transfer-Encoding", "gzip, chunked"), ("Content-Length", str(len(body)))]
    head = f"{method} {target} HTTP/1.1\r\n" + "".join(f"{k}: {v}\r\n" for k, v in headers)
    head += "Connection: close\r\n\r\n"
    incomplete = framing in ("long", "bad-chunk", "negative", "junk", "gzip") or (framing == "none" and method == "POST")
    return head.encode("utf-8", "surrogatepass") + body, method, path, incomplete


def answered(reply: bytes) -> bool:
    """Whether `reply` holds a whole answer: its headers and Content-Length bytes of body."""
    head, sep, body = reply.partition(b"\r\n\r\n")
    m = re.search(rb"\r\ncontent-length: *(\d+)", head, re.IGNORECASE)
    return bool(sep and m and len(body) >= int(m.group(1)))


def send(data: bytes, port: int, incomplete: bool = False) -> tuple:
    """(status or None, body) of one request. A request whose framing promises more than it
    sends would keep the server waiting for its read timeout: its write side is closed at once,
    which ends it there (the server may then close without an answer). Any other request must
    be answered within 60 s."""
    with socket.create_connection(("127.0.0.1", port), timeout=60) as s:
        try:
            s.sendall(data)
            if incomplete:
                s.shutdown(socket.SHUT_WR)
        except OSError:
            pass  # the server may answer and close before reading everything
        chunks = []
        while True:
            try:
                chunk = s.recv(65536)
            except socket.timeout:
                raise TimeoutError("no answer within 60 s")
            except ConnectionResetError:
                break
            if not chunk:
                break
            chunks.append(chunk)
            if answered(b"".join(chunks)):
                break  # a connection the server keeps open after a malformed request line
    reply = b"".join(chunks)
    m = re.match(rb"HTTP/1\.[01] (\d{3})", reply)
    return (int(m.group(1)) if m else None), reply.split(b"\r\n\r\n", 1)[-1]


def resident_mib(pid: int) -> float:
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return -1.0


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("svr")
    ap.add_argument("--requests", type=int, default=4000)
    ap.add_argument("--seconds", type=float, default=120)
    ap.add_argument("--seed", type=int, default=41)
    ap.add_argument("--max-growth-mib", type=float, default=192)
    a = ap.parse_args()
    with tempfile.TemporaryDirectory(prefix="svr_view_fuzz_") as scratch:
        scene = os.path.join(scratch, "sphere.json")
        with open(scene, "w") as f:
            json.dump(SCENE, f, indent=1)
        return fuzz(a, scene)


def fuzz(a, scene: str) -> int:
    # ASan keeps 256 MiB of freed memory in quarantine by default, which would read as growth:
    # a small quarantine leaves what the server itself holds (other builds ignore the option).
    env = dict(os.environ)
    env["ASAN_OPTIONS"] = ":".join(filter(None, [env.get("ASAN_OPTIONS", ""), "quarantine_size_mb=8"]))
    proc = subprocess.Popen([a.svr, "view", scene, "--port", "0", "--renderer", "raycast",
                             "--token", TOKEN], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, env=env)
    m = re.search(r"http://127\.0\.0\.1:(\d+)/", proc.stdout.readline())
    if not m:
        proc.kill()
        print("FAIL: svr view printed no URL:", proc.stderr.read()[-2000:])
        return 1
    port = int(m.group(1))
    health = f"GET /api/scene?token={TOKEN} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nConnection: close\r\n\r\n".encode()
    problems, statuses = [], collections.Counter()
    rng = random.Random(a.seed)
    send(health, port)
    rss0 = resident_mib(proc.pid)
    rss_half = rss0
    t0, n = time.monotonic(), 0
    while n < a.requests and time.monotonic() - t0 < a.seconds and proc.poll() is None:
        data, method, path, incomplete = request(rng, port)
        try:
            status, body = send(data, port, incomplete)
        except TimeoutError:
            problems.append(f"no answer within 60 s to {data[:200]!r}")
            status, body = "timeout", b""
        except OSError as e:
            status, body = None, str(e).encode()
        if status is None and not incomplete:
            problems.append(f"closed without an answer: {data[:200]!r}")
        statuses[str(status)] += 1
        render_failure = status == 500 and path == "/api/render" and b'"error"' in body
        if isinstance(status, int) and status >= 500 and not (render_failure or status == 503):
            problems.append(f"{status} for {data[:200]!r}: {body[:200]!r}")
        n += 1
        if n % 200 == 0 and send(health, port)[0] != 200:
            problems.append(f"after {n} requests /api/scene is not answered 200")
        if n == a.requests // 2:
            rss_half = resident_mib(proc.pid)
    seconds = time.monotonic() - t0
    alive = proc.poll() is None
    final = send(health, port)[0] if alive else None
    rss1 = resident_mib(proc.pid) if alive else -1
    proc.send_signal(signal.SIGINT)
    try:
        _, err = proc.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        _, err = proc.communicate()
        problems.append("svr view did not stop within 60 s of SIGINT")
    if not alive:
        problems.append(f"svr view died (exit {proc.returncode})")
    if final != 200:
        problems.append(f"at the end /api/scene answers {final}")
    if proc.returncode != 0:
        problems.append(f"svr view exited {proc.returncode}")
    for marker in ("ERROR: AddressSanitizer", "ERROR: LeakSanitizer", "runtime error:"):
        if marker in err:
            problems.append(f"{marker} in its stderr: {err[err.index(marker):][:1500]}")
    if rss1 - rss0 > a.max_growth_mib:
        problems.append(f"resident memory grew {rss1 - rss0:.0f} MiB (limit {a.max_growth_mib:.0f})")
    if rss1 - rss_half > a.max_growth_mib / 4:
        problems.append(f"resident memory grew {rss1 - rss_half:.0f} MiB over the second half")
    print(json.dumps({"requests": n, "seconds": round(seconds, 1), "seed": a.seed,
                      "statuses": dict(sorted(statuses.items())),
                      "rss_mib": {"start": round(rss0), "half": round(rss_half), "end": round(rss1)}}))
    for p in problems[:20]:
        print("FAIL:", p)
    if not problems:
        print(f"ok: {n} random requests in {seconds:.0f} s, no crash, no unexplained 5xx, memory held")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
