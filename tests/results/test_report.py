"""HTML report: one self-contained page with scenario, summary and limits, figures and provenance."""

from __future__ import annotations

import base64
import importlib.util
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path

import matplotlib
import pytest

from tb_exudyn.report import code_limit, find_results, summary, write_report

matplotlib.use("Agg")
_spec = importlib.util.spec_from_file_location(
    "synthetic_results", Path(__file__).resolve().parents[1] / "plotting" / "synthetic_results.py")
synthetic = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(synthetic)

CH = "car1.axle1.force_y"


class Page(HTMLParser):
    """Tables (id -> rows of cell texts), image sources, tags and every resource reference."""

    def __init__(self, text: str):
        super().__init__()
        self.tables: dict[str, list[list[str]]] = {}
        self.images: list[str] = []
        self.tags: set[str] = set()
        self.refs: list[str] = []
        self._table = self._row = self._cell = None
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        self.tags.add(tag)
        self.refs += [v for k, v in attrs if k in ("src", "href") and v]
        if tag == "img":
            self.images.append(a["src"])
        elif tag == "table":
            self._table = self.tables.setdefault(a["id"], [])
        elif tag == "tr":
            self._row = []
            self._table.append(self._row)
        elif tag in ("td", "th"):
            self._cell = []

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self._row.append(" ".join("".join(self._cell).split()))
            self._cell = None

    def handle_data(self, data):
        if self._cell is not None:
            self._cell.append(data)


def _row(table, first):
    (row,) = [r for r in table if r[0] == first]
    return row


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("results")
    synthetic.pem_response().save(d / "pem")
    synthetic.mc_response().save(d / "mc")
    synthetic.time_history().save(d / "det")
    return d


@pytest.fixture(scope="module")
def report(folder):
    return write_report(folder, channels=[CH])


def test_report_holds_the_tables(report):
    page = Page(report.read_text(encoding="utf-8"))
    for tid in ("scenario-train", "scenario-vehicle-ice_motor", "scenario-bridge", "scenario-track",
                "scenario-settings", "scenario-derived", "scenario-sources", "summary-pem", "summary-mc",
                "summary-det", "provenance-pem", "provenance-mc", "provenance-det"):
        assert tid in page.tables, tid
    assert _row(page.tables["scenario-settings"], "speed_kmh")[1:3] == ["250", "km/h"]
    assert _row(page.tables["scenario-bridge"], "spans")[1:3] == ["32", "m"]
    assert _row(page.tables["scenario-derived"], "first axle enters")[1] == f"{30 / (250 / 3.6):.6g}"
    assert _row(page.tables["provenance-mc"], "seed")[1] == "1"
    assert _row(page.tables["provenance-pem"], "versions.numpy")[1]
    head = page.tables["summary-pem"][0]
    assert head == ["channel", "unit", "max |mean|", "max sigma", "max |mean| + 3 sigma", "limit", "margin", "status"]


def test_summary_and_limits(report):
    pem = synthetic.pem_response()
    page = Page(report.read_text(encoding="utf-8"))
    rows = {r.channel: r for r in summary(pem)}
    deck = _row(page.tables["summary-pem"], "bridge.span1.mid.acc_z")
    assert deck[4] == f"{rows['bridge.span1.mid.acc_z'].peak:.4g}"
    assert deck[5].startswith("3.5 [check]") and "ballasted" in deck[5]
    assert deck[6] == f"{3.5 - rows['bridge.span1.mid.acc_z'].peak:.4g}" and deck[7] == "OK"
    assert _row(page.tables["summary-pem"], "car1.axle1.left.force_z")[5:] == ["", "", ""]  # no limit
    det = _row(page.tables["summary-det"], "car1.body.acc_y")  # synthetic history peaks at 2 > 1.0 m/s^2
    assert det[2] == "2" and det[3].startswith("1 [check]") and det[4] == "-1" and det[5] == "EXCEEDS"


def test_code_limits():
    sc = synthetic.scenario()
    assert code_limit("bridge.span2.q1.acc_z", sc).value == 3.5
    assert code_limit("bridge.pier1.top.acc_z", sc) is None and code_limit("bridge.span1.mid.acc_y", sc) is None
    assert code_limit("car1.body.acc_z", sc).value == 1.3 and code_limit("car1.body.acc_y", sc).value == 1.0
    p_st_kn = (48000 + 2 * 3200 + 4 * 2400) * 9.81 / 4 / 1e3  # ICE motor car, its weight on four axles
    assert code_limit("car1.axle3.force_y", sc).value == pytest.approx(0.85 * (10 + p_st_kn / 3) * 1e3, rel=1e-12)
    assert code_limit("car1.axle3.force_z", sc) is None and code_limit("car2.axle1.force_y", sc) is None


def test_report_is_self_contained(report):
    text = report.read_text(encoding="utf-8")
    page = Page(text)
    assert "script" not in page.tags and "link" not in page.tags
    assert len(page.images) == 5  # pem: bounds + psd map, mc: bounds, det: history, pem vs mc
    for src in page.images:
        assert src.startswith("data:image/png;base64,")
        assert base64.b64decode(src.split(",", 1)[1])[:4] == b"\x89PNG"
    assert all(ref.startswith(("data:", "#")) for ref in page.refs), page.refs


def test_text_is_escaped_and_single_result_folder(tmp_path):
    sc = synthetic.scenario().replace(description='<script>alert("x")</script> & <b>bold</b>')
    th = synthetic.time_history()
    type(th)(time=th.time, channels=th.channels, units=th.units, scenario=sc,
             provenance={"note": "<img src=x>"}).save(tmp_path / "det")
    out = write_report(tmp_path / "det", tmp_path / "page.html", channels="car1.body.acc_y")
    text = out.read_text(encoding="utf-8")
    assert "<script>" not in text and "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt; &amp; &lt;b&gt;" in text
    assert "&lt;img src=x&gt;" in text and len(Page(text).images) == 1
    assert [p.name for p, _ in find_results(tmp_path)] == ["det"]


@pytest.mark.skipif(shutil.which("chromium") is None, reason="chromium not installed (apt-get install chromium)")
def test_report_renders_in_headless_chromium(report):
    dom = subprocess.run(
        ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--dump-dom", report.resolve().as_uri()],
        capture_output=True, text=True, timeout=60, check=True,
    ).stdout
    page = Page(dom)
    assert {"summary-pem", "summary-mc", "scenario-train", "provenance-det"} <= set(page.tables)
    assert len(page.images) == 5
    assert _row(page.tables["summary-det"], "car1.body.acc_y")[5] == "EXCEEDS"
