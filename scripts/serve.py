#!/usr/bin/env python3
"""Serves the viewer page and one .dtm stream on 127.0.0.1, optionally throttled.

    serve.py DIST_DIR [FILE.dtm] [--port N] [--rate 500KB/s] [--throttle-all]

The page's files come from DIST_DIR (build-wasm/dist); the stream is served
at /stream.dtm (and under its own name), so that

    http://127.0.0.1:PORT/?stream=stream.dtm

shows it. --rate sends the stream no faster than that many bytes per second
(decimal units: 500KB/s = 500,000 bytes/s; B, KB, MB, GB), in small chunks,
flushed one by one, so that the levels arrive in the browser as they would
over a slow network; --throttle-all throttles the page's own files too.
Only the loopback interface listens. Prints the URL on one line, then serves
until interrupted. --port 0 (the default) picks a free port.
"""
import argparse
import http.server
import os
import re
import sys
import time
import urllib.parse

CHUNK = 4096


def parse_rate(text):
    m = re.fullmatch(r"\s*([0-9]*\.?[0-9]+)\s*(B|KB|MB|GB)(/s)?\s*", text, re.IGNORECASE)
    if not m:
        raise argparse.ArgumentTypeError(f"'{text}' is not a rate such as 500KB/s or 1MB/s")
    value = float(m.group(1)) * {"B": 1, "KB": 1e3, "MB": 1e6, "GB": 1e9}[m.group(2).upper()]
    if value <= 0:
        raise argparse.ArgumentTypeError("the rate must be positive")
    return value


def make_handler(dist, stream, rate, throttle_all):
    stream_names = set()
    if stream:
        stream_names = {"/stream.dtm", "/" + urllib.parse.quote(os.path.basename(stream))}

    class Handler(http.server.SimpleHTTPRequestHandler):
        extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                          ".dtm": "application/octet-stream", ".wasm": "application/wasm",
                          ".mjs": "text/javascript", ".js": "text/javascript"}

        def __init__(self, *args, **kwargs):
            super().__init__(*args, directory=dist, **kwargs)

        def translate_path(self, path):
            if urllib.parse.urlsplit(path).path in stream_names:
                return stream
            return super().translate_path(path)

        def end_headers(self):
            self.send_header("Cache-Control", "no-store")
            super().end_headers()

        def copyfile(self, source, destination):
            path = urllib.parse.urlsplit(self.path).path
            if rate is None or not (throttle_all or path in stream_names):
                return super().copyfile(source, destination)
            start, sent = time.monotonic(), 0
            try:
                while chunk := source.read(CHUNK):
                    destination.write(chunk)
                    destination.flush()
                    sent += len(chunk)
                    delay = start + sent / rate - time.monotonic()
                    if delay > 0:
                        time.sleep(delay)
            except (BrokenPipeError, ConnectionResetError):
                pass  # the page went away (a new file, a closed tab)

        def log_message(self, format, *args):
            if os.environ.get("DTM_SERVE_LOG"):
                super().log_message(format, *args)

    return Handler


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dist", help="the page's folder (build-wasm/dist)")
    parser.add_argument("stream", nargs="?", help="the .dtm file to serve as /stream.dtm")
    parser.add_argument("--port", type=int, default=0, help="port on 127.0.0.1 (0: any free port)")
    parser.add_argument("--rate", type=parse_rate, help="throttle the stream: 500KB/s, 1MB/s (decimal units)")
    parser.add_argument("--throttle-all", action="store_true", help="throttle the page's files too")
    args = parser.parse_args()
    if not os.path.isfile(os.path.join(args.dist, "index.html")):
        sys.exit(f"serve.py: {args.dist} holds no viewer page (index.html): run scripts/build_web.sh")
    if args.stream and not os.path.isfile(args.stream):
        sys.exit(f"serve.py: {args.stream}: no such file")
    stream = os.path.abspath(args.stream) if args.stream else None
    handler = make_handler(os.path.abspath(args.dist), stream, args.rate, args.throttle_all)
    try:
        server = http.server.ThreadingHTTPServer(("127.0.0.1", args.port), handler)
    except OSError as e:
        sys.exit(f"serve.py: cannot listen on 127.0.0.1:{args.port}: {e.strerror}")
    query = "?stream=stream.dtm" if stream else ""
    print(f"http://127.0.0.1:{server.server_address[1]}/{query}", flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()


if __name__ == "__main__":
    main()
