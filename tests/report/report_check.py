#!/usr/bin/env python3
"""`usm report` and `usm map`, end to end.

    report_check.py PATH/TO/usm

Builds the report (--quick) into a temporary directory and checks that
 - report.md starts with usm's marker line;
 - every file it links (Markdown images and links) exists, PNGs are PNGs
   (signature, IHDR, plausible size) and SVGs parse as XML with root <svg>;
 - every CSV file a gnuplot script reads exists;
 - the paper-vs-computed table (section 2) contains every number the paper
   publishes, and no value is missing ("n/a", "not found");
 - a report usm wrote is overwritten, anything else only with --force;
 - `usm map` writes its CSV/JSON, the same for 1 and 2 threads, and rejects
   bad options (exit 2, one line);
 - the design figures: the datasheet (speed, power, efficiency vs
   T) and the elasticity chart are linked and valid; report.json's power
   numbers equal an independent `usm steady --json`, its sensitivities an
   independent `usm sensitivity --json`; the datasheet CSV obeys
   P_out = T w_R, eta = P_out / P_in and the power balance; the chart's CSV
   holds the nonzero elasticities sorted by magnitude; section 8 quotes them.
 - the non-ideal motor (section 9): each tolerable phase error
   and mode split of report.json is bracketed by independent `usm periodic
   --variant imperfect --set NAME=X` runs (F_n_min > 0 and max |lambda| < 1
   just below it, F_n_min < 0 or max |lambda| > 1 just above, whichever the
   report names); a curve point equals an independent run; report.md states
   each tolerable value with its model; the orbit figure's data close (first
   point = last) and its ideal circle's radius is `usm steady`'s theta.
Exit 77 (ctest: skipped) when gnuplot is not installed.
"""
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET

USM = sys.argv[1]
failures = []

# The paper's published numbers as printed, from the one file that holds them
# (data/paper_values.json; sections 3, 5, 6, Tables 3 and 4, the text on
# Figs. 9 and 10).  The report must show each of them.
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "data",
                       "paper_values.json"), encoding="utf-8") as _f:
    _paper = json.load(_f)
PUBLISHED = [v["printed"] for v in _paper.values() if isinstance(v, dict)] + \
    [x for t in ("table3", "table4") for m in _paper[t] for x in (m["printed"],
                                                                  m["modulus_printed"])]
if len(PUBLISHED) < 22:
    sys.exit("paper_values.json: fewer published values than the paper has")


def fail(msg):
    print("FAIL", msg)
    failures.append(msg)


def ok(msg):
    print("ok  ", msg)


def run(*args):
    return subprocess.run([USM, *args], capture_output=True, text=True)


def check_png(path):
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(b"\x89PNG\r\n\x1a\n"):
        return "no PNG signature"
    if data[12:16] != b"IHDR":
        return "no IHDR chunk"
    w, h = struct.unpack(">II", data[16:24])
    if not (200 <= w <= 5000 and 200 <= h <= 5000):
        return f"implausible size {w}x{h}"
    if len(data) < 5000:
        return f"only {len(data)} bytes"
    return None


def check_svg(path):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        return f"not XML: {e}"
    if root.tag.split("}")[-1] != "svg":
        return f"root element is <{root.tag}>, not <svg>"
    if len(list(root.iter())) < 20:
        return "almost empty"
    return None


def check_report(out):
    md_path = os.path.join(out, "report.md")
    with open(md_path, encoding="utf-8") as f:
        md = f.read()
    if md.splitlines()[0].startswith("<!-- usm report:"):
        ok("report.md starts with the usm marker")
    else:
        fail("report.md lacks the marker line")
    # the contents list every section, in order
    sections = re.findall(r"^## (\d+)\. (.+)$", md, re.M)
    listed = re.findall(r"^(\d+)\. \[([^\]]+)\]\(#[^)]+\)$", md, re.M)
    if sections and sections == listed:
        ok(f"the contents list all {len(sections)} sections")
    else:
        fail(f"contents {listed} differ from the sections {sections}")
    # keys outside the plots they would cover
    for name in ("fig11_speed_amplitude", "datasheet", "nonideal_curves", "nonideal_orbit"):
        with open(os.path.join(out, name + ".gp"), encoding="utf-8") as f:
            keys = re.findall(r"^\s*set key (.*)$", f.read(), re.M)
        if keys and all(re.match(r"(below|above|outside|[tblr]margin)\b", k) for k in keys):
            ok(f"{name}.gp: the key outside the plot ({keys[0].split()[0]})")
        else:
            fail(f"{name}.gp: a key inside the plot: {keys}")
    # fig. 11's existence limits inside the frame, not on it
    with open(os.path.join(out, "fig11_speed_amplitude.gp"), encoding="utf-8") as f:
        fig11 = f.read()
    if "graph 0 to" not in fig11 and "set offsets" in fig11:
        ok("fig11: the existence lines end inside the frame, the ranges padded")
    else:
        fail("fig11: the existence lines run from frame to frame")
    # the imperfections are usm's choice, not the paper's
    for name in ("amp_imbalance", "phase_error", "mode_split"):
        row = re.search(rf"^\| `{name}` \|.*$", md, re.M)
        if row and "Table 5" not in row.group(0) and "chosen by usm" in row.group(0):
            ok(f"{name} is credited to usm, not to the paper")
        else:
            fail(f"{name}'s parameter row: {row.group(0) if row else 'missing'}")

    # report.json: every number by name; report.md shows the same numbers
    try:
        with open(os.path.join(out, "report.json"), encoding="utf-8") as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        fail(f"report.json: {e}")
        data = None
    if data is not None:
        shown = [f"{data['model']['3dof']['theta']:.6g} rad",
                 f"{data['model']['4dof']['rotor_speed']:.6g} 1/s",
                 f"{data['characteristics']['located']['stick_limit']['Nmm']:.4g} N mm"]
        missing = [t for t in shown if t not in md]
        if missing:
            fail(f"report.md does not show report.json's {missing}")
        else:
            ok("report.md shows report.json's numbers")
        if data["paper"]["theta3"]["printed"] == _paper["theta3"]["printed"]:
            ok("report.json holds the paper's values as loaded")
        else:
            fail("report.json: the paper's values differ from data/paper_values.json")
        # the maps' largest |lambda| printed with enough digits that a value
        # below 1 does not read as 1 (0.99999 was printed "1")
        for m in data["maps"]:
            t = re.search(rf"Judged by the smallest-tilt root alone, {m['unstable']} cells are "
                          r"unstable \(largest \|λ\| ([^)]+)\); where F_t <= mu0 F_n, \d+ "
                          r"\(largest \|λ\| ([^)]+)\)", md)
            shown = [float(x) for x in t.groups()] if t else []
            want = [m["max_modulus"], m["max_modulus_stick"]]
            if t and all((a < 1) == (b < 1) and close(a, b, 1e-5) for a, b in zip(shown, want)):
                ok(f"{m['name']}: largest |lambda| shown as {t.group(1)}, {t.group(2)}")
            else:
                fail(f"{m['name']}: largest |lambda| shown {shown}, report.json {want}")
        check_design(out, md, data)
        check_nonideal(out, md, data)
        check_validity(out, md, data)
        check_squeal_validity(out, md, data)
        check_maps(out, md, data)
        check_envelope(out, md, data)

    images = re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", md)
    links = [t for t in re.findall(r"(?<!!)\[[^\]]*\]\(([^)\s]+)\)", md)
             if not t.startswith(("#", "http:", "https:"))]
    pngs = [t for t in images + links if t.endswith(".png")]
    svgs = [t for t in images + links if t.endswith(".svg")]
    if len(set(pngs)) >= 7 and len(set(svgs)) >= 7:
        ok(f"report links {len(set(pngs))} PNG and {len(set(svgs))} SVG figures")
    else:
        fail(f"report links only {len(set(pngs))} PNG and {len(set(svgs))} SVG figures")
    for name in sorted(set(images + links)):
        path = os.path.join(out, name)
        if not os.path.isfile(path):
            fail(f"{name}: linked but missing")
            continue
        err = check_png(path) if name.endswith(".png") else \
            check_svg(path) if name.endswith(".svg") else None
        if err:
            fail(f"{name}: {err}")
        else:
            ok(f"{name}: valid")
    for name in images:
        if not name.endswith(".png"):
            fail(f"embedded image {name} is not a PNG")

    # every data file a script reads exists and has a header and data
    for gp in sorted(n for n in os.listdir(out) if n.endswith(".gp")):
        with open(os.path.join(out, gp), encoding="utf-8") as f:
            text = f.read()
        for csv in sorted(set(re.findall(r'"([\w.-]+\.csv)"', text))):
            path = os.path.join(out, csv)
            if not os.path.isfile(path):
                fail(f"{gp} reads {csv}, which is missing")
                continue
            with open(path, encoding="utf-8") as f:
                lines = [l for l in f.read().splitlines() if l.strip()]
            if len(lines) < 2 and not csv.endswith(("_stability.csv", "_existence.csv",
                                                     "_stick.csv")):
                fail(f"{csv}: no data rows")
        ok(f"{gp}: its CSV files exist")

    # the comparison table holds every published number
    m = re.search(r"^## 2\..*?(?=^## 3\.)", md, re.S | re.M)
    if not m:
        fail("no section 2 (the paper's numbers beside the computed ones)")
        return
    table = "\n".join(l for l in m.group(0).splitlines() if l.startswith("|"))
    for number in PUBLISHED:
        if number in table:
            ok(f"table shows the published {number!r}")
        else:
            fail(f"table lacks the published {number!r}")
    rows = [l for l in table.splitlines()[2:]]
    if len(rows) >= 20:
        ok(f"table has {len(rows)} rows")
    else:
        fail(f"table has only {len(rows)} rows")
    for bad in ("n/a", "not found"):
        if bad in md:
            fail(f"report contains {bad!r}: a value was not computed")
    # the variants section: every generated model, t0 dependence stated for each
    out_v = subprocess.run([USM, "variants"], capture_output=True, text=True).stdout
    models = [(b if v == "paper" else f"{b}_{v}") for v, bases, *_ in
              (l.split(None, 2) for l in out_v.splitlines()) for b in bases.split(",")]
    m = re.search(r"^## 7\. Modelling variants.*?(?=^## 8\.)", md, re.S | re.M)
    if not m:
        fail("no section 7 (modelling variants side by side)")
    else:
        rows = {r.split("|")[1].strip(" `"): r for r in m.group(0).splitlines()
                if r.startswith("| `")}
        for name in models:
            row = rows.get(name)
            if row is None:
                fail(f"variants section lacks {name}")
            elif not row.rstrip(" |").endswith(("yes", "no")):
                fail(f"variants section: {name} has no t0 verdict")
            else:
                ok(f"variants section shows {name}")
        for name, dep in (("3dof", "yes"), ("3dof_twist_integrated", "no")):
            if name in rows and not rows[name].rstrip(" |").endswith(dep):
                fail(f"variants section: {name} should say t0 dependence {dep}")
    for key in ("Table 3 uses t0 = 0", "f = 37000 Hz", "2 I_R / R^2"):
        if key in md:
            ok(f"report states {key!r}")
        else:
            fail(f"report does not state {key!r}")


def close(a, b, rel=1e-9, absolute=1e-300):
    return a is not None and b is not None and abs(a - b) <= max(rel * max(abs(a), abs(b)),
                                                                 absolute)


def read_csv(path):
    import csv
    with open(path, encoding="utf-8") as f:
        return list(csv.DictReader(f))


def num_or_none(x):
    return float(x) if x not in ("", None) else None


def check_design(out, md, data):
    """The datasheet and the elasticity chart."""
    images = set(re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", md))
    for fig in ("datasheet", "elasticity"):
        if f"{fig}.png" in images and f"{fig}.svg" in md:
            ok(f"report.md shows the {fig} figure")
        else:
            fail(f"report.md lacks the {fig} figure")
    m = re.search(r"^## 8\. Design.*?(?=^## 9\.)", md, re.S | re.M)
    sec = m.group(0) if m else ""
    if not sec:
        fail("no section 8 (design: power, efficiency and sensitivities)")
    for model in ("3dof", "4dof"):
        # power on the operating point against an independent `usm steady`
        r = run("steady", "--model", model, "--json")
        try:
            st = json.loads(r.stdout)
        except ValueError:
            fail(f"usm steady --model {model} --json: exit {r.returncode} {r.stderr}")
            continue
        rep = data["model"][model]
        keys = ("power_in", "power_out", "power_damping", "power_slip", "efficiency",
                "rotor_speed")
        bad = [k for k in keys if not close(rep.get(k), st.get(k), 1e-9, 1e-15)]
        if bad:
            fail(f"{model}: report.json's {bad} differ from usm steady --json")
        else:
            ok(f"{model}: report.json's power and efficiency equal usm steady --json")

        # sensitivities against an independent `usm sensitivity`
        r = run("sensitivity", "--model", model, "--of", "rotor_speed,max_modulus", "--json")
        try:
            sj = json.loads(r.stdout)["outputs"]
        except (ValueError, KeyError):
            fail(f"usm sensitivity --model {model} --json: exit {r.returncode} {r.stderr}")
            continue
        for out_name in ("rotor_speed", "max_modulus"):
            rs = data["sensitivity"][model][out_name]
            cmd = sj[out_name]
            bad = [p for p, e in cmd["elasticity"].items()
                   if not (e is None and rs["elasticity"][p] is None)
                   and not close(e, rs["elasticity"][p], 1e-8, 1e-12)]
            if close(rs["value"], cmd["value"], 1e-9) and not bad:
                ok(f"{model} {out_name}: value and 19 elasticities equal usm sensitivity --json")
            else:
                fail(f"{model} {out_name}: differs from usm sensitivity --json "
                     f"({rs['value']} vs {cmd['value']}; {bad})")
            # ranked: the nonzero ones, by decreasing magnitude
            want = sorted((p for p, e in cmd["elasticity"].items() if e),
                          key=lambda p: -abs(cmd["elasticity"][p]))
            got = [x["parameter"] for x in rs["ranked"]]
            mags = [abs(cmd["elasticity"][p]) for p in got]
            if sorted(got) == sorted(want) and mags == sorted(mags, reverse=True):
                ok(f"{model} {out_name}: {len(got)} nonzero elasticities ranked by magnitude")
            else:
                fail(f"{model} {out_name}: ranking {got} is not {want}")
            rows = read_csv(os.path.join(out, f"elasticity_{out_name}_{model}.csv"))
            if [r_["parameter"] for r_ in rows] == got and all(
                    close(float(r_["elasticity [1]"]), x["elasticity"], 1e-12)
                    for r_, x in zip(rows, rs["ranked"])):
                ok(f"elasticity_{out_name}_{model}.csv holds the ranking")
            else:
                fail(f"elasticity_{out_name}_{model}.csv differs from report.json's ranking")
            top = rs["ranked"][0] if rs["ranked"] else None
            if top and (f"{top['parameter']} ({top['elasticity']:+.3g})" in sec or
                        f"{top['parameter']} {top['elasticity']:+.3g})" in sec):
                ok(f"section 8 quotes the largest {model} {out_name} elasticity")
            else:
                fail(f"section 8 does not quote the largest {model} {out_name} elasticity")

        # the datasheet's data: closed-form identities at every point
        rows = read_csv(os.path.join(out, f"datasheet_{model}.csv"))
        worst = 0.0
        n = 0
        for r_ in rows:
            if r_["converged"] != "true":
                continue
            T = float(r_["T [N m]"])
            w = float(r_["speed [1/s]"])
            pin, pout = float(r_["power_in [W]"]), float(r_["power_out [W]"])
            pd, ps = float(r_["power_damping [W]"]), float(r_["power_slip [W]"])
            eta = num_or_none(r_["efficiency [1]"])
            worst = max(worst, abs(pout - T * w) / max(abs(pin), 1e-300),
                        abs(pin - pout - pd - ps) / abs(pin),
                        abs(eta - pout / pin) if eta is not None else 0.0)
            n += 1
        if n >= 10 and worst < 1e-9:
            ok(f"datasheet_{model}.csv: {n} points, P_out = T w_R, balance and eta = P_out/P_in "
               f"to {worst:.1e}")
        else:
            fail(f"datasheet_{model}.csv: {n} points, worst relative {worst:.2e}")
        # its first point (T = 0) against an independent `usm steady --set T=0`
        r = run("steady", "--model", model, "--set", "T=0", "--json")
        try:
            st0 = json.loads(r.stdout)
            first = rows[0]
            good = float(first["T [N m]"]) == 0 and close(float(first["speed [1/s]"]),
                                                          -st0["rotor_speed"], 1e-7) \
                and close(float(first["power_in [W]"]), st0["power_in"], 1e-7)
        except (ValueError, KeyError, IndexError):
            good = False
        if good:
            ok(f"datasheet_{model}.csv at T = 0 equals usm steady --set T=0")
        else:
            fail(f"datasheet_{model}.csv at T = 0 differs from usm steady --set T=0")
        # the key numbers: the grid maximum of the efficiency
        ds = data["datasheet"][model]
        cands = [float(r_["efficiency [1]"]) for r_ in rows if r_["converged"] == "true"
                 and r_["efficiency [1]"] and (model == "4dof" or
                                               r_["stick_admissible"] == "true")]
        if cands and close(max(cands), ds["efficiency_max"], 1e-12) and \
                f"{ds['efficiency_max']:.3g} at T = {ds['efficiency_max_T_Nmm']:.3g} N mm" in sec:
            ok(f"{model}: largest efficiency {ds['efficiency_max']:.3g} from the CSV, quoted")
        else:
            fail(f"{model}: datasheet efficiency_max {ds.get('efficiency_max')} vs CSV "
                 f"{max(cands) if cands else None}")


def check_validity(out, md, data):
    """Validity: every data row says whether the model
    describes the motor, and the stated valid range of the 3-DOF load curve is
    the stick_limit event of an independent `usm sweep` over the same grid."""
    rows = read_csv(os.path.join(out, "fig10_speed_load_3dof.csv"))
    conv = [r_ for r_ in rows if r_["converged"] == "true"]
    # valid exactly where stick is admissible (3-DOF; the contact is closed)
    if conv and all((r_["valid"] == "true") == (r_["stick_admissible"] == "true") and
                    r_["invalid_reason"] == ("" if r_["valid"] == "true" else
                                             "stick_not_admissible") for r_ in conv):
        ok(f"fig10_speed_load_3dof.csv: valid = stick_admissible on {len(conv)} rows")
    else:
        fail("fig10_speed_load_3dof.csv: valid differs from stick_admissible")
    Ts = [float(r_["T [N m]"]) for r_ in rows]
    r = run("sweep", "--model", "3dof", "--over", "T", "--from", repr(Ts[0]), "--to",
            repr(Ts[-1]), "--points", str(len(Ts)), "--no-floquet", "--json")
    try:
        ev = [e["T"] for e in json.loads(r.stdout)["events"] if e["type"] == "stick_limit"]
    except (ValueError, KeyError):
        ev = []
    curve = [c for c in data["characteristics"]["curves"]
             if c["over"] == "T" and c["model"] == "3dof"]
    iv = curve[0]["valid"]["intervals"] if curve else []
    if len(ev) == 1 and len(iv) == 1 and iv[0]["to_by"] == "stick_limit" and \
            close(iv[0]["to"], ev[0], 1e-9) and iv[0]["from"] == Ts[0] and \
            data["datasheet"]["3dof"]["valid"]["intervals"] == iv:
        ok(f"3-DOF load curve valid for T <= {iv[0]['to']:.10g} N m: the sweep's stick_limit "
           f"{ev[0]:.10g}")
    else:
        fail(f"3-DOF valid range {iv} vs the sweep's stick_limit {ev}")
    bad = [float(r_["T [N m]"]) for r_ in conv if r_["valid"] == "false"]
    if ev and bad and min(bad) > ev[0]:
        ok("the first invalid row of the load curve lies past the stick limit")
    else:
        fail(f"first invalid row {min(bad) if bad else None} vs stick limit {ev}")
    stated = f"valid for T <= {ev[0] * 1e3:.4g} N mm (stick limit" if ev else None
    texts = [c["valid"]["text"] for c in data["characteristics"]["curves"]]
    if stated and stated in md and all(t and t in md for t in texts):
        ok(f"report.md states every curve's valid range ({stated}...)")
    else:
        fail(f"report.md does not state the valid ranges {texts}")
    # the datasheet's power and efficiency know it too
    ds = read_csv(os.path.join(out, "datasheet_3dof.csv"))
    if ds and all((r_["valid"] == "true") == (r_["converged"] == "true" and
                                              r_["stick_admissible"] == "true")
                  for r_ in ds if r_["converged"] == "true"):
        ok("datasheet_3dof.csv: valid on every row")
    else:
        fail("datasheet_3dof.csv: valid differs from stick_admissible")
    # the non-ideal curves: valid up to valid_to, not beyond
    ni = data.get("nonideal", {})
    for model in ("3dof", "4dof"):
        for imp in ("phase_error", "mode_split"):
            if not ni.get("ok"):
                continue
            v = ni[model][imp]["valid_to"]
            rows = read_csv(os.path.join(out, f"nonideal_curves_{imp}_{model}.csv"))
            col = f"{imp} [{'rad' if imp == 'phase_error' else '1'}]"
            good = all((r_["valid"] == "true") == (not v["found"] or float(r_[col]) < v["value"])
                       for r_ in rows if r_["converged"] == "true")
            # and the reason matches the orbit: contact open iff F_n_min <= 0
            good = good and all((r_["invalid_reason"] == "contact_open") ==
                                (float(r_["F_n_min [N]"]) <= 0)
                                for r_ in rows if r_["converged"] == "true")
            if good:
                ok(f"nonideal_curves_{imp}_{model}.csv: valid up to {v['value'] if v['found'] else 'the end'}")
            else:
                fail(f"nonideal_curves_{imp}_{model}.csv: valid rows vs valid_to {v}")


def check_squeal_validity(out, md, data):
    """A value of an orbit the model does not describe is printed with its
    flag in every output: the squeal frequency of the Neimark-Sacker point
    (8.6 % mode split, far past contact loss at 1.33 %) in report.json,
    squeal_values.csv, report.md (hence report.html) and the figure; the
    bilateral orbit there judged by an independent `usm periodic` run.  The
    openings are counted on the orbit (twice a period for the mode split's
    2 Omega wobble; the text said "once"), and e_impact is usm's assumption,
    not the paper's Table 5."""
    sq = data.get("squeal", {})
    if not sq.get("ok"):
        fail(f"squeal not computed: {sq.get('note')}")
        return
    r = run("periodic", "--model", "4dof", "--set", f"mode_split={sq['ns_value']!r}", "--json")
    try:
        orbit = json.loads(r.stdout)
    except ValueError:
        orbit = {}
    invalid = orbit.get("F_n_min", 0) < 0
    if invalid and sq.get("ns_valid") is False and sq.get("ns_invalid_reason") == "contact_open":
        ok(f"squeal at {sq['ns_percent']:.4g} %: report.json flags it (F_n_min {orbit['F_n_min']:.3g} N)")
    else:
        fail(f"squeal: ns_valid {sq.get('ns_valid')}, the orbit's F_n_min {orbit.get('F_n_min')}")
    vals = read_csv(os.path.join(out, "squeal_values.csv"))
    if vals and vals[0].get("valid") == ("false" if invalid else "true") and \
            vals[0].get("invalid_reason") == ("contact_open" if invalid else ""):
        ok("squeal_values.csv: the squeal frequency with its validity")
    else:
        fail(f"squeal_values.csv: {vals[:1]}")
    amp = read_csv(os.path.join(out, "squeal_amplitude.csv"))
    if amp and all(a.get("valid") in ("true", "false") for a in amp):
        ok("squeal_amplitude.csv: every orbit's row with its validity")
    else:
        fail(f"squeal_amplitude.csv: no validity column: {list(amp[0]) if amp else None}")
    m = re.search(r"\*\*f_s = [0-9.]+ kHz\*\*([^(]*\([^)]*\))?", md)
    if m and (("**model invalid** there: contact_open" in m.group(0)) == invalid):
        ok("report.md: the squeal frequency carries its flag")
    else:
        fail(f"report.md: the squeal frequency's text: {m.group(0) if m else None}")
    svg = os.path.join(out, "squeal.svg")
    if os.path.exists(svg):
        if ("model invalid: contact_open" in open(svg).read()) == invalid:
            ok("squeal.svg: the labels carry the flag")
        else:
            fail("squeal.svg: the squeal frequency's labels have no flag")
    opened = data["nonideal"]["4dof"]["mode_split"]["contact_open"]
    if "opens once a" not in md and "once a cycle" not in md and opened.get("openings") == 2 and \
            "opens twice a period" in md:
        ok("report.md: the contact opens twice a period along the mode split (counted)")
    else:
        fail(f"report.md: openings not counted: {opened}")
    # the orbits with separation: the last stable one's speed carries its flag,
    # judged by an independent usm periodic at that value
    for model in ("3dof", "4dof"):
        for imp in ("phase_error", "mode_split"):
            sp = data["nonideal"][model][imp].get("separating", {})
            if sp.get("last") is None:
                continue
            r = run("periodic", "--model", model, "--variant", "imperfect_unilateral",
                    "--set", f"{imp}={sp['last']!r}", "--json")
            try:
                valid = json.loads(r.stdout)["valid"]
            except (ValueError, KeyError):
                valid = None
            cell = re.search(r"1/s at [0-9.]+( \(\*\*model invalid\*\*: ([a-z_]+)\))?",
                             md[md.find(f"({data['nonideal'][model]['unilateral_model']})"):]) \
                if imp == "phase_error" else None
            if valid is not None and sp.get("last_valid") == valid and \
                    (cell is None or (cell.group(1) is None) == valid):
                ok(f"{model} {imp}: the last stable orbit with separation, valid {valid}, so flagged")
            else:
                fail(f"{model} {imp}: last_valid {sp.get('last_valid')}, usm periodic valid {valid}")
    e = [p_ for p_ in data["parameters"] if p_["name"] == "e_impact"]
    if e and "not in the paper" in e[0]["source"] and "Table 5" not in e[0]["source"]:
        ok("e_impact: usm's assumption, not Table 5")
    else:
        fail(f"e_impact's source: {e}")


def periodic(model, name, value):
    """An independent `usm periodic` run: (F_n_min, max |lambda|, JSON)."""
    r = run("periodic", "--model", model, "--variant", "imperfect", "--set",
            f"{name}={value!r}", "--json")
    try:
        obj = json.loads(r.stdout)
        return obj["F_n_min"], obj["floquet"]["max_modulus"], obj
    except (ValueError, KeyError, TypeError):
        fail(f"usm periodic --model {model} --set {name}={value}: exit {r.returncode}: "
             f"{r.stderr.strip()}")
        return None, None, None


# The figure's labels of the operating point's classes (data/plots/map_3dof.gp,
# map_4dof.gp) and the CSV's op_class names; "invalid" is the dots (column valid).
MAP_LABELS = {"operating point": "operating_point", "no stable root": "no_stable_root",
              "does not start from rest": "does_not_start", "unknown": "unknown",
              "no stationary solution": "no_solution", "model not valid here": "invalid"}


def svg_texts(path):
    """The text of every <text> element of an SVG (tspans joined)."""
    return ["".join(e.itertext()).strip() for e in ET.parse(path).iter()
            if e.tag.split("}")[-1] == "text"]


def check_maps(out, md, data):
    """The stability maps by the operating point: report.json's class
    counts are the CSV's; report.md states them and says the maps are computed
    without --from-rest; every class the figure's legend names exists in the CSV
    with the count it gives, every class absent from the CSV is stated absent
    under the legend, and the two together are every class."""
    sections = md.split("![Stability map f x T, ")
    for k, model in enumerate(("3dof", "4dof")):
        name = f"map_{model}"
        rows = read_csv(os.path.join(out, f"{name}.csv"))
        count = {c: sum(r["op_class"] == c for r in rows) for c in
                 ("operating_point", "no_stable_root", "does_not_start", "unknown",
                  "no_solution", "not_evaluated")}
        count["invalid"] = sum(r["valid"] == "false" for r in rows)
        summary = [m for m in data["maps"] if m["name"] == name]
        if not summary:
            fail(f"report.json has no map {name}")
            continue
        js = summary[0]
        want = dict(js["classes"], invalid=js["invalid"])
        if want == count and sum(count[c] for c in js["classes"]) == len(rows) and \
                js["several_roots"] == sum(int(r["roots"]) > 1 for r in rows):
            ok(f"report.json {name}: class counts equal the CSV's {count}")
        else:
            fail(f"report.json {name}: classes {want} vs the CSV's {count}")
        absent = [l for l, c in MAP_LABELS.items() if c != "invalid" and count[c] == 0]
        if js["absent"] != ", ".join(absent):
            fail(f"report.json {name}: absent {js['absent']!r}, the CSV has none of {absent}")
        # report.md: the table of this map (after its figure) gives the CSV's counts
        text = next((t for t in sections[1:] if t.startswith(("3-DOF", "4-DOF")[k])), "")
        text = text.split("\n## ")[0]
        shown = {c: re.search(r"^\| %s[^|]*\| (\d+) \|$" % re.escape(l), text, re.M)
                 for l, c in MAP_LABELS.items() if c != "invalid"}
        if all(m and int(m.group(1)) == count[c] for c, m in shown.items()) and \
                (not absent or f"Not on this map: {', '.join(absent)}." in text) and \
                f"at {count['invalid']} of the" in text:
            ok(f"report.md states {name}'s class counts and its absent classes")
        else:
            fail(f"report.md: {name}'s counts { {c: m and m.group(1) for c, m in shown.items()} } "
                 f"vs the CSV's {count}")
        # the legend: "LABEL (N cells)" for each class present, the absent ones under it
        svg = os.path.join(out, f"{name}.svg")
        if not os.path.exists(svg):
            continue  # no plots: check_report names the missing figure
        texts = svg_texts(svg)
        legend = {}
        for t in texts:
            m = re.match(r"^(.*?)(?: \(several roots\))? \((\d+) cells?\)$", t)
            if m:
                legend[m.group(1)] = int(m.group(2))
        notes = [t for t in texts if t.startswith("Classes not on this map: ") or
                 t == "the model is valid at every cell"]
        stated = []
        for t in notes:
            for part in t.split("; "):
                if part.startswith("Classes not on this map: "):
                    stated += part[len("Classes not on this map: "):].split(", ")
                elif part == "the model is valid at every cell":
                    stated.append("model not valid here")
        bad = [l for l in legend if l not in MAP_LABELS or legend[l] != count[MAP_LABELS[l]]
               or legend[l] == 0]
        bad += [l for l in stated if l not in MAP_LABELS or count[MAP_LABELS[l]] != 0]
        missing = [l for l, c in MAP_LABELS.items() if (l in legend) == (l in stated)]
        if not bad and not missing and legend:
            ok(f"{name}.svg: the legend names {sorted(legend)} with the CSV's counts; "
               f"stated absent: {stated}")
        else:
            fail(f"{name}.svg: legend {legend}, stated absent {stated}: wrong {bad}, "
                 f"neither or both {missing}")
    for phrase in ("without `--from-rest`", "is **unknown**"):
        if phrase not in md:
            fail(f"report.md section 6 does not say {phrase!r}")


def check_envelope(out, md, data):
    """Section 12: the operating envelope over f x F0 from rest.  The
    codimension-two point where the fold is born on the start threshold is
    the one `usm envelope --x f:36kHz:40kHz --y F0:0.1:2 --from-rest` locates
    and AUTO-07p confirms (docs/envelope.md): f = 37010.456 Hz, F0 = 0.99997 N."""
    en = data.get("envelope", {})
    if not en.get("ok"):
        fail(f"report.json: the envelope not computed: {en.get('note')}")
        return
    m = re.search(r"^## 12\. The operating envelope.*?(?=^## )", md, re.S | re.M)
    sec = m.group(0) if m else ""
    if not sec:
        fail("no section 12 (the operating envelope)")
    images = set(re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", sec))
    if "envelope.png" in images and "envelope.svg" in sec:
        ok("section 12 shows the envelope figure")
    else:
        fail("section 12 lacks the envelope figure")
    for name in ("envelope.png", "envelope.svg", "envelope.gp", "envelope.csv"):
        if not os.path.exists(os.path.join(out, name)):
            fail(f"the envelope figure's {name} is missing")
    kinds = sorted({c["kind"] for c in en.get("curves", [])})
    if kinds == ["fold", "tilt_zero"]:
        ok("report.json envelope: the curves tilt_zero and fold")
    else:
        fail(f"report.json envelope: curve kinds {kinds}, want fold and tilt_zero")
    pts = [c for c in en.get("codim2", []) if c["type"] == "tilt_zero/fold"]
    if len(pts) == 1 and close(pts[0]["f"], 37010.456, 1e-6) and close(pts[0]["F0"], 0.99997, 1e-6):
        ok(f"envelope: the codimension-two point at f = {pts[0]['f']:.8g} Hz, F0 = {pts[0]['F0']:.6g} N")
    else:
        fail(f"envelope: codimension-two points {en.get('codim2')}, want tilt_zero/fold at "
             "37010.456 Hz, 0.99997 N")
    classes = sorted(r["class"] for r in en.get("regions", []))
    if classes == ["does_not_start", "no_solution", "operating_point"]:
        ok("envelope: three regions (operating_point, no_solution, does_not_start)")
    else:
        fail(f"envelope: regions {classes}")
    if pts and f"f = {pts[0]['f']:.8g} Hz, F0 = {pts[0]['F0']:.6g} N" in sec:
        ok("section 12 states the codimension-two point")
    else:
        fail("section 12 does not state the codimension-two point")


def check_nonideal(out, md, data):
    """Section 9: the non-ideal motor."""
    ni = data.get("nonideal", {})
    if not ni.get("ok"):
        fail(f"report.json: the non-ideal motor not computed: {ni.get('note')}")
        return
    m = re.search(r"^## 9\. The non-ideal motor.*", md, re.S | re.M)
    sec = m.group(0) if m else ""
    if not sec:
        fail("no section 9 (the non-ideal motor)")
    images = set(re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", sec))
    for fig in ("nonideal_curves", "nonideal_orbit"):
        if f"{fig}.png" in images and f"{fig}.svg" in sec:
            ok(f"section 9 shows the {fig} figure")
        else:
            fail(f"section 9 lacks the {fig} figure")
    # the tolerable values against independent runs on each side: the report
    # locates them to 1e-9 of the range, the test brackets them at 1e-3
    delta = 1e-3
    for model in ("3dof", "4dof"):
        for name, unit in (("phase_error", "degrees"), ("mode_split", "%")):
            cv = ni[model][name]
            tol = cv["tolerable"]
            if not tol["found"]:
                f_end, l_end, _ = periodic(model, name, cv["to"])
                if f_end is not None and f_end > 0 and l_end < 1:
                    ok(f"{model} {name}: no limit up to {cv['to']:g}, as usm periodic says")
                else:
                    fail(f"{model} {name}: the report finds no limit, but at {cv['to']:g} "
                         f"F_n_min = {f_end}, max |lambda| = {l_end}")
                continue
            x = tol["value"]
            f_lo, l_lo, _ = periodic(model, name, x * (1 - delta))
            f_hi, l_hi, _ = periodic(model, name, x * (1 + delta))
            if f_lo is None or f_hi is None:
                continue
            below = f_lo > 0 and l_lo < 1
            above = f_hi < 0 if tol["by"] == "contact" else l_hi > 1
            if below and above:
                ok(f"{model} {name}: tolerable {x:.6g} ({tol['by']}) bracketed by usm periodic: "
                   f"F_n_min {f_lo:.3g} / {f_hi:.3g}, max |lambda| {l_lo:.6g} / {l_hi:.6g}")
            else:
                fail(f"{model} {name}: tolerable {x:.6g} ({tol['by']}) not confirmed: "
                     f"F_n_min {f_lo} / {f_hi}, max |lambda| {l_lo} / {l_hi}")
            said = f"{tol['display']:.3g} {unit}"
            if said in sec and data["nonideal"][model]["model"] in sec:
                ok(f"section 9 states the {model} tolerable {name}: {said}")
            else:
                fail(f"section 9 does not state the {model} tolerable {name} {said!r}")
    # a curve point (the warm-started last one) against an independent run
    rows = read_csv(os.path.join(out, "nonideal_curves_phase_error_4dof.csv"))
    last = rows[-1]
    f_ind, l_ind, obj = periodic("4dof", "phase_error", float(last["phase_error [rad]"]))
    if obj is not None and close(float(last["F_n_min [N]"]), f_ind, 1e-6) and \
            close(float(last["max_modulus [1]"]), l_ind, 1e-6) and \
            close(float(last["rotor_speed_ripple [1/s]"]), obj["rotor_speed_ripple"], 1e-5):
        ok("the last 4-DOF phase-error point equals usm periodic's (F_n_min, |lambda|, ripple)")
    else:
        fail(f"the last 4-DOF phase-error point {last} differs from usm periodic's "
             f"{f_ind}, {l_ind}")
    # past contact loss: the curves continue with the unilateral
    # model's orbits with separation; a point (the 4-DOF phase error's last)
    # against an independent `usm periodic --variant imperfect_unilateral`
    # (solved from a simulation, not warm-started: measured 1e-10 for the
    # mean speed, 1e-8 for the ripple, 2e-9 for the impact velocity); the
    # separating rows are the bilateral orbits whose contact opens; section 9
    # states the largest impact velocity
    for model in ("3dof", "4dof"):
        for imp in ("phase_error", "mode_split"):
            rows_ = read_csv(os.path.join(out, f"nonideal_curves_{imp}_{model}.csv"))
            sep = ni[model][imp].get("separating", {})
            opened = [r_ for r_ in rows_ if r_["converged"] == "true" and
                      float(r_["F_n_min [N]"]) < 0]
            seprows = [r_ for r_ in rows_ if r_.get("separating") == "true"]
            if seprows and seprows == opened and sep.get("points") == len(seprows):
                ok(f"{model} {imp}: {len(seprows)} orbits with separation past contact loss")
            else:
                fail(f"{model} {imp}: orbits with separation {len(seprows)} vs contact open "
                     f"{len(opened)} (report.json: {sep.get('points')})")
                continue
            # over the stable orbits: an unstable one is not what the motor does
            vmax = max((float(r_["impact_velocity_max [m/s]"]) for r_ in seprows
                        if float(r_["max_modulus_separating [1]"] or "nan") < 1), default=None)
            if vmax is None:
                if sep.get("impact_velocity_max") is None:
                    ok(f"{model} {imp}: no stable orbit with separation, no impact velocity given")
                else:
                    fail(f"{model} {imp}: an impact velocity without a stable orbit")
                continue
            said = f"**{vmax * 1e3:.3g}**"
            if close(vmax, sep["impact_velocity_max"], 1e-12) and said in sec:
                ok(f"section 9 states the {model} {imp} largest impact velocity {said} mm/s")
            else:
                fail(f"section 9 lacks the {model} {imp} largest impact velocity {said}")
    rows = read_csv(os.path.join(out, "nonideal_curves_phase_error_4dof.csv"))
    last = [r_ for r_ in rows if r_.get("separating") == "true"][-1:]
    if last:
        last = last[0]
        v = float(last["phase_error [rad]"])
        r = run("periodic", "--model", "4dof", "--variant", "imperfect_unilateral", "--set",
                f"phase_error={v!r}", "--json")
        try:
            obj = json.loads(r.stdout)
        except ValueError:
            obj = {}
        pairs = (("rotor_speed_mean_separating [1/s]", "rotor_speed_mean", 1e-8),
                 ("rotor_speed_ripple_separating [1/s]", "rotor_speed_ripple", 1e-6),
                 ("impact_velocity_max [m/s]", "impact_velocity_max", 1e-7),
                 ("separation_fraction [1]", "separation_fraction", 1e-7))
        if obj.get("contact_open") and all(close(float(last[a]), obj.get(b, float("nan")), t)
                                           for a, b, t in pairs):
            ok(f"the 4-DOF orbit with separation at {v:.6g} rad equals usm periodic's (speed "
               f"{obj['rotor_speed_mean']:.8g}, ripple {obj['rotor_speed_ripple']:.6g} 1/s, "
               f"impact {obj['impact_velocity_max']:.6g} m/s)")
        else:
            fail(f"the 4-DOF orbit with separation {last} differs from usm periodic's {obj}")
    else:
        fail("nonideal_curves_phase_error_4dof.csv: no orbit with separation")
    # the orbit: one closed period; the ideal circle of radius usm steady's theta
    orbit = read_csv(os.path.join(out, "nonideal_orbit.csv"))
    circle = read_csv(os.path.join(out, "nonideal_orbit_circle.csv"))
    xs = [float(r["rho_X [rad]"]) for r in orbit]
    ys = [float(r["rho_Y [rad]"]) for r in orbit]
    span = float(orbit[-1]["t [s]"]) - float(orbit[0]["t [s]"])
    step = max(((xs[i + 1] - xs[i]) ** 2 + (ys[i + 1] - ys[i]) ** 2) ** 0.5
               for i in range(len(xs) - 1))
    radius = max(abs(x) for x in xs)
    if len(orbit) == ni["orbit"]["samples"] and close(xs[0], xs[-1], 1e-9, 1e-9 * radius) and \
            close(ys[0], ys[-1], 1e-9, 1e-9 * radius) and \
            close(span, 1.0 / data["params"]["f"], 1e-9) and step < 0.1 * radius:
        ok(f"the orbit closes after one period ({len(orbit)} points, largest step "
           f"{step / radius:.3g} of the radius)")
    else:
        fail(f"the orbit does not close: first ({xs[0]}, {ys[0]}), last ({xs[-1]}, {ys[-1]}), "
             f"span {span}, largest step {step}")
    r = run("steady", "--json")
    try:
        theta = json.loads(r.stdout)["theta"]
    except (ValueError, KeyError):
        theta = None
    radii = [(float(c["rho_X [rad]"]) ** 2 + float(c["rho_Y [rad]"]) ** 2) ** 0.5 for c in circle]
    if theta is not None and all(close(q, theta, 1e-9) for q in radii):
        ok(f"the ideal circle's radius is usm steady's theta {theta:.6g} rad")
    else:
        fail(f"the ideal circle's radius {radii[:2]} is not usm steady's theta {theta}")
    # the circle is drawn where the orbit is, centred at the origin:
    # its points' mean is ~0 against the radius, and the script adds no shift
    cx = sum(float(c["rho_X [rad]"]) for c in circle) / len(circle)
    cy = sum(float(c["rho_Y [rad]"]) for c in circle) / len(circle)
    with open(os.path.join(out, "nonideal_orbit.gp"), encoding="utf-8") as f:
        gp = f.read()
    drawn = re.search(r'circ using \(column\("rho_X \[rad\]"\) \* 1e6\):'
                      r'\(column\("rho_Y \[rad\]"\) \* 1e6\)', gp)
    if radii and max(abs(cx), abs(cy)) < 0.05 * max(radii) and drawn:
        ok("the ideal circle is centred at the origin, as drawn")
    else:
        fail(f"the ideal circle's centre ({cx}, {cy}) or its plot command is shifted")


def expect_bad(args, field):
    r = run(*args)
    lines = r.stderr.splitlines()
    if r.returncode == 2 and len(lines) == 1 and lines[0].startswith("usm: ") and \
            field in lines[0] and not r.stdout:
        ok(f"usm {' '.join(args)}: exit 2, {lines[0]}")
    else:
        fail(f"usm {' '.join(args)}: exit {r.returncode}, stderr {r.stderr!r}")


def main():
    gnuplot = os.environ.get("USM_GNUPLOT") or "gnuplot"
    if not shutil.which(gnuplot):
        print(f"SKIP: {gnuplot} not found (install gnuplot-nox)")
        sys.exit(77)
    tmp = tempfile.mkdtemp(prefix="usm-report-")
    try:
        out = os.path.join(tmp, "rep")
        r = run("report", "--out", out, "--quick")
        if r.returncode != 0:
            fail(f"usm report exited {r.returncode}: {r.stderr}")
            return
        ok(f"usm report --quick: {r.stdout.strip()}")
        check_report(out)

        # its own report is overwritten
        r = run("report", "--out", out, "--quick", "--no-plots")
        if r.returncode == 0:
            ok("a second run overwrites usm's own report")
        else:
            fail(f"second run into the same directory: exit {r.returncode}: {r.stderr}")

        # a report.md usm did not write is kept
        mine = os.path.join(tmp, "mine")
        os.mkdir(mine)
        with open(os.path.join(mine, "report.md"), "w") as f:
            f.write("# my notes\n")
        expect_bad(["report", "--out", mine, "--quick", "--no-plots"], "report.md")
        with open(os.path.join(mine, "report.md")) as f:
            if f.read() == "# my notes\n":
                ok("a foreign report.md is left untouched")
            else:
                fail("a foreign report.md was changed")
        # and so is any file of the report's names without a usm report.md
        other = os.path.join(tmp, "other")
        os.mkdir(other)
        with open(os.path.join(other, "map_3dof.csv"), "w") as f:
            f.write("mine\n")
        expect_bad(["report", "--out", other, "--quick", "--no-plots"], "map_3dof.csv")
        r = run("report", "--out", mine, "--quick", "--no-plots", "--force")
        if r.returncode == 0:
            ok("--force overwrites")
        else:
            fail(f"--force: exit {r.returncode}: {r.stderr}")

        # bad options
        expect_bad(["report"], "--out")
        expect_bad(["report", "--out", out, "--model", "4dof"], "--model")
        expect_bad(["report", "--out", out, "--threads", "0"], "--threads")
        expect_bad(["report", "--out", out, "--set", "m0=abc"], "m0")
        expect_bad(["report", "--out", out, "--bogus"], "--bogus")

        # usm map
        r = run("map", "--x-points", "3", "--y-points", "2", "--threads", "2")
        rows = r.stdout.splitlines()
        if r.returncode == 0 and rows[0].startswith("f [Hz],T [N m],exists,roots,max_modulus [1],") and \
                len(rows) == 7:
            ok("usm map: CSV with header and 6 rows")
        else:
            fail(f"usm map CSV: exit {r.returncode}, {rows[:2]}, {r.stderr}")
        one = run("map", "--x-points", "5", "--y-points", "4", "--threads", "1", "--json")
        two = run("map", "--x-points", "5", "--y-points", "4", "--threads", "2", "--json")
        if one.returncode == 0 and one.stdout == two.stdout:
            ok("usm map: the same output from 1 and 2 threads")
        else:
            fail("usm map: the output depends on the number of threads")
        r = run("map", "--model", "4dof", "--x", "m0", "--x-from", "0.003", "--x-to", "0.006",
                "--x-points", "3", "--y-points", "3", "--y-to", "0.0012", "--json")
        try:
            obj = json.loads(r.stdout)
            good = (r.returncode == 0 and obj["model"] == "4dof" and len(obj["points"]) == 9
                    and obj["x"]["name"] == "m0" and set(obj["boundaries"]) ==
                    {"existence", "stability", "stick"})
        except (ValueError, KeyError):
            good = False
        if good:
            ok("usm map --json: 9 points, boundaries")
        else:
            fail(f"usm map --json: exit {r.returncode}: {r.stdout[:200]} {r.stderr}")
        # --out writes what stdout shows, and says nothing (it exited 1
        # with "write error" although the file was complete)
        grid = ["map", "--x-points", "2", "--y-points", "2"]
        shown = run(*grid)
        new_out = os.path.join(tmp, "map_new.csv")
        written = run(*grid, "--out", new_out)
        text = open(new_out).read() if os.path.exists(new_out) else None
        if (shown.returncode == 0 and written.returncode == 0 and written.stderr == ""
                and text == shown.stdout and len(text.splitlines()) == 5):
            ok("usm map --out: exit 0, silent, the file equal to stdout's table")
        else:
            fail(f"usm map --out: exit {written.returncode}, stderr {written.stderr!r}, "
                 f"file {'equal' if text == shown.stdout else 'different'}")
        csv_out = os.path.join(tmp, "map.csv")
        with open(csv_out, "w") as f:
            f.write("keep\n")
        expect_bad(["map", "--x-points", "2", "--y-points", "2", "--out", csv_out], "exists")
        expect_bad(["map", "--x", "nosuch"], "nosuch")
        expect_bad(["map", "--x", "m0"], "--x-from")
        expect_bad(["map", "--x-points", "1"], "--x-points")
        expect_bad(["map", "--y", "f"], "--y")
        expect_bad(["map", "--x", "m0", "--x-from", "-1", "--x-to", "1"], "m0")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


main()
if failures:
    print(f"FAILED: {len(failures)} check(s)")
    sys.exit(1)
print("usm report and usm map: all checks passed")
