#!/usr/bin/env python3
"""Checks an `sds score --format html` page against the JSON report of the same run.

Parses the page with Python's html.parser (no third-party package) and asserts: every route of
the JSON report has its row in the route table and its drill-down; every number of the route
table equals the JSON report's (the exact value in `data-v`, the rounded text too); each route
has one figure per aligned collision, its comfort timeline lists as many failed chunks as the
report counts, its lateral timeline as many anomalous and critical chunks; the headline numbers
match the summary; the waterfall carries the summary's decomposition and the route chart every
route in its order; nothing is loaded from outside the file.

usage: html_report_check.py REPORT.html REPORT.json
"""
import json
import sys
from html.parser import HTMLParser


class Page(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.rows = []          # route table rows: (attrs, [(cell attrs, text)])
        self.details = {}       # drill-down id -> {"route", "figures", "comfort", "lateral"}
        self.external = []      # src/href pointing outside the file
        self.ids = set()
        self.scripts = 0
        self._table = None
        self._row = None
        self._cell = None
        self._detail = None
        self._fig = 0
        self.sds = None
        self._in_sds = False
        self.figures = {}       # picture id -> its attributes and the number of <svg> inside
        self._picture = None

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        for key in ("src", "href"):
            v = a.get(key)
            if v and not v.startswith("#"):
                self.external.append((tag, key, v))
        if tag == "link" or (tag == "script" and "src" in a):
            self.external.append((tag, "link/script", a))
        if tag == "script":
            self.scripts += 1
        if tag == "table" and a.get("id") == "routes":
            self._table = a
        if tag == "tr" and self._table is not None and "data-route" in a:
            self._row = (a, [])
        if tag == "td" and self._row is not None:
            self._cell = [a, ""]
        if tag == "details" and "route" in a.get("class", ""):
            self._detail = a["id"]
            self.details[a["id"]] = {"route": a.get("data-route"), "figures": 0}
        if tag == "div" and self._detail:
            cls = a.get("class", "")
            if cls == "fig":
                self.details[self._detail]["figures"] += 1
            if "timeline comfort" in cls:
                self.details[self._detail]["comfort"] = a
            if "timeline lateral" in cls:
                self.details[self._detail]["lateral"] = a
        if tag == "b" and a.get("id") == "sds":
            self._in_sds = True
        if tag == "figure" and a.get("id") in ("waterfall", "route-chart"):
            self._picture = a["id"]
            self.figures[a["id"]] = dict(a, svgs=0, rects=0)
        if self._picture and tag == "svg":
            self.figures[self._picture]["svgs"] += 1
        if self._picture and tag == "rect":
            self.figures[self._picture]["rects"] += 1

    def handle_endtag(self, tag):
        if tag == "td" and self._cell is not None:
            self._row[1].append((self._cell[0], self._cell[1].strip()))
            self._cell = None
        if tag == "tr" and self._row is not None:
            self.rows.append(self._row)
            self._row = None
        if tag == "table":
            self._table = None
        if tag == "details":
            self._detail = None
        if tag == "b":
            self._in_sds = False
        if tag == "figure":
            self._picture = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell[1] += data
        if self._in_sds:
            self.sds = data.strip()


def fmt(v, digits):
    return "-" if v is None else f"{v:.{digits}f}"


def main(html_path, json_path):
    page = Page()
    with open(html_path, encoding="utf-8") as f:
        page.feed(f.read())
    with open(json_path, encoding="utf-8") as f:
        report = json.load(f)
    problems = []

    def check(ok, msg):
        if not ok:
            problems.append(msg)

    routes = report["routes"]
    check(not page.external, f"the page loads from outside: {page.external[:3]}")
    check(page.scripts == 1, f"{page.scripts} scripts, expected 1 inline script")
    check(len(page.rows) == len(routes), f"{len(page.rows)} rows for {len(routes)} routes")
    check(page.sds == fmt(report["summary"]["sds"], 2), f"headline SDS {page.sds}")
    columns = ["route", "state", "town", "scenario", "status", "rc", "penalty", "ds", "ds_safe",
               "comfort", "comfort_moving",
               "stationary", "collisions",
               "decelerated", "nodecel", "exempt", "unaligned", "anomalous", "critical", "warnings"]
    for i, (r, (attrs, cells)) in enumerate(zip(routes, page.rows)):
        rid = r["route_id"] or "<no route_id>"
        check(attrs["data-route"] == rid, f"row {i}: {attrs['data-route']} != {rid}")
        check(len(cells) == len(columns), f"{rid}: {len(cells)} cells")
        cell = dict(zip(columns, cells))
        ev = r["collision_events"]
        aligned = [e for e in ev if e["frame"] is not None]
        c = r["collisions"]
        expect = {
            "rc": (r["score_route"], 2),
            "penalty": (r["score_penalty"], 3),
            "ds": (r["score_composed"], 2),
            "ds_safe": (r["ds_safe"], 2),
            "comfort": (r["comfort"]["score"], 3),
            "comfort_moving": (r["comfort"]["moving_score"], 3),
            "stationary": (None if r["stationary_share"] is None else 100 * r["stationary_share"], 1),
            "collisions": (c["pedestrian"] + c["vehicle"] + c["layout"], 0),
            "decelerated": (sum(1 for e in aligned if e["decelerated"] and not e["exempt"]), 0),
            "nodecel": (c["nodecel"], 0),
            "exempt": (c["exempt"], 0),
            "unaligned": (c["unaligned"], 0),
            "anomalous": (r["lateral"]["anomalous"], 0),
            "critical": (r["lateral"]["critical"], 0),
            "warnings": (len(r.get("warnings", [])), 0),
        }
        for col, (value, digits) in expect.items():
            a, text = cell[col]
            got = a.get("data-v")
            want = "" if value is None else value
            check(got is not None and ((got == "" and want == "") or
                                       (got != "" and want != "" and float(got) == float(want))),
                  f"{rid} {col}: data-v {got!r}, JSON {value!r}")
            check(text == fmt(value, digits), f"{rid} {col}: text {text!r}, JSON {value!r}")
        check(cell["route"][1] == rid, f"{rid}: route cell {cell['route'][1]!r}")
        # The status cell says why the DS is what it is: the status, RC × penalty in its title.
        status_attrs, status = cell["status"]
        check(status == (r["status"] or "-"), f"{rid}: status {status!r}, JSON {r['status']!r}")
        if r["score_route"] is not None and r["score_penalty"] is not None:
            check(f"RC {r['score_route']:.2f} × penalty " in status_attrs.get("title", ""),
                  f"{rid}: status title {status_attrs.get('title')!r}")
        check(attrs["data-state"] == str(r["state"]).split(":")[0],
              f"{rid}: state {attrs['data-state']} vs {r['state']}")
        target = attrs["data-target"]
        d = page.details.get(target)
        check(d is not None and d["route"] == rid, f"{rid}: no drill-down {target}")
        if d is None:
            continue
        check(d["figures"] == len(aligned), f"{rid}: {d['figures']} figures, {len(aligned)} aligned")
        if "comfort" in d:
            comfort = r["comfort"]
            check(int(d["comfort"]["data-chunks"]) == comfort["chunks"], f"{rid}: comfort chunks")
            check(int(d["comfort"]["data-failed"]) == comfort["chunks"] - comfort["comfortable"],
                  f"{rid}: failed comfort chunks")
            lat = r["lateral"]
            check(int(d["lateral"]["data-chunks"]) == lat["chunks"], f"{rid}: lateral chunks")
            check(int(d["lateral"]["data-anomalous"]) == lat["anomalous"], f"{rid}: anomalous")
            check(int(d["lateral"]["data-critical"]) == lat["critical"], f"{rid}: critical")
        else:
            check(r["frames"] == 0, f"{rid}: replayed but no timeline")
    # The pictures above the tables: the waterfall draws the JSON's decomposition, the route
    # chart every route, sorted by DS then DS_safe (descending), then input order.
    dec = report["summary"]["decomposition"]
    w = page.figures.get("waterfall")
    if dec is None:
        check(w is None and "waterfall-none" in page.ids, "a waterfall without a decomposition")
    else:
        check(w is not None and w["svgs"] == 1, "no waterfall picture")
        if w is not None:
            for attr, key in (("data-ds", "ds"), ("data-ds-safe", "ds_safe"), ("data-sds", "sds")):
                want = dec[key]
                got = w.get(attr)
                check((got == "" and want is None) or (want is not None and got and float(got) == want),
                      f"waterfall {attr} {got!r}, JSON {want!r}")
            steps = w["data-steps"].split(";")
            check(steps[0].startswith("DS=") and float(steps[-1].split("=")[1]) ==
                  (dec["sds"] if dec["sds"] is not None else dec["ds_safe"]), f"waterfall steps {steps}")
            check(w["rects"] == 1 + len(steps), f"waterfall: {w['rects']} rects for {len(steps)} bars")
    c = page.figures.get("route-chart")
    check(c is not None and c["svgs"] == 1, "no route chart")
    if c is not None:
        key = lambda i: (-(routes[i]["score_composed"] or 0.0),
                         -(routes[i]["ds_safe"] if routes[i]["ds_safe"] is not None else float("-inf")), i)
        want = [routes[i]["route_id"] or "<no route_id>" for i in sorted(range(len(routes)), key=key)]
        check(c["data-order"].split(" ") == want, f"route chart order {c['data-order']!r}, expected {want}")
        check(int(c["data-routes"]) == len(routes), "route chart: route count")
        safe = sum(1 for r in routes if r["ds_safe"] is not None)
        check(c["rects"] == 1 + len(routes) + safe + 5,
              f"route chart: {c['rects']} rects for {len(routes)} routes, {safe} with DS_safe")
    for needed in ("routes", "filter", "state", "status", "warnings", "tables"):
        check(needed in page.ids, f"no element #{needed}")
    if problems:
        for p in problems[:30]:
            print(f"html check: {p}", file=sys.stderr)
        print(f"html check: FAILED ({len(problems)} problem(s)) on {html_path}", file=sys.stderr)
        return 1
    figures = sum(d["figures"] for d in page.details.values())
    print(f"html check: ok: {len(routes)} routes, {figures} figures, {len(page.figures)} pictures, every number equal to the JSON report")
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:3]))
