# SPDX-License-Identifier: LGPL-2.1-or-later
"""Document round trip between FreeCAD versions, second half (run with freecadcmd):
  MFGEOM_ROUNDTRIP_DIR=DIR freecadcmd tests/freecad/roundtrip_check.py
opens DIR/roundtrip.FCStd (written by roundtrip_save.py, usually on another FreeCAD
version) and checks, object by object, against DIR/roundtrip.json:
  * the proxy as saved (Document.xml: module, class and the state {"Type", "Version"}
    that __getstate__ / dumps wrote) and as restored (Proxy.Type, Version, valid);
  * the results as restored from the file, without a recompute;
  * the results after every mfgeom object is touched and the document recomputed
    (floats within roundtrip_common.REL), and the clearance check of the sweep;
  * then that the document saved again on this version reopens with the same results.
Prints one line per check and "roundtrip-check: N passed, M failed (saved by FreeCAD A,
checked on B)"; exits 0 when all passed."""

import json
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import roundtrip_common as rc  # noqa: E402

import FreeCAD as App  # noqa: E402

results = []  # (name, ok, detail)


def record(name, problems):
    results.append((name, not problems, "; ".join(problems[:8])))


def check_objects(doc, saved, stage):
    for name, want in sorted(saved["objects"].items()):
        obj = doc.getObject(name)
        if obj is None:
            record(f"{stage}: {name}", ["missing from the document"])
            continue
        problems = []
        proxy = getattr(obj, "Proxy", None)
        if getattr(proxy, "Type", None) != want["type"]:
            problems.append(f"Proxy.Type {getattr(proxy, 'Type', None)!r}, "
                            f"saved {want['type']!r}")
        if not obj.isValid():
            problems.append(f"invalid: {obj.getStatusString()}")
        problems += rc.differences(want["results"], rc.summary(obj), name)
        record(f"{stage}: {name} ({want['type']})", problems)


def check_proxy_states(fcstd, saved, stage):
    states = rc.saved_proxy_states(fcstd)
    for name, want in sorted(saved["objects"].items()):
        got = states.get(name)
        problems = []
        if got is None:
            problems.append("no Proxy in Document.xml")
        else:
            if got["state"] != {"Type": want["type"], "Version": want["version"]}:
                problems.append(f"saved state {got['state']!r}")
            if not (got["module"] or "").startswith("mfgeom.app."):
                problems.append(f"proxy module {got['module']!r}")
        record(f"{stage}: proxy of {name} as saved", problems)


def main():
    fcstd, json_path = rc.paths()
    with open(json_path, encoding="utf-8") as f:
        saved = json.load(f)
    here = rc.freecad_version()
    check_proxy_states(fcstd, saved, "file")
    doc = App.openDocument(fcstd)
    check_objects(doc, saved, "restored")
    for obj in doc.Objects:
        if getattr(getattr(obj, "Proxy", None), "Type", "").startswith("Mfgeom::"):
            obj.touch()
    doc.recompute()
    check_objects(doc, saved, "recomputed")
    got = rc.clearance_results(doc)
    record("recomputed: clearance check of the sweep",
           rc.differences(saved["clearance"], got, "clearance"))
    # saved again on this version: the proxies write their state, the file reopens
    with tempfile.TemporaryDirectory(prefix="mfgeom-roundtrip-") as tmp:
        again = os.path.join(tmp, "again.FCStd")
        doc.saveAs(again)
        App.closeDocument(doc.Name)
        check_proxy_states(again, saved, "saved again")
        doc = App.openDocument(again)
        check_objects(doc, saved, "reopened")
        App.closeDocument(doc.Name)
    failed = [r for r in results if not r[1]]
    for name, ok, detail in results:
        sys.stdout.write(f"{'PASS' if ok else 'FAIL'}: {name}" + (f": {detail}" if detail else "")
                         + "\n")
    sys.stdout.write(f"roundtrip-check: {len(results) - len(failed)} passed, {len(failed)} "
                     f"failed (saved by FreeCAD {saved['freecad']}, checked on {here})\n")
    return 1 if failed or not results else 0


rc.run_main(main)
