#include "app/test_report.h"

#include <algorithm>
#include <cstdio>

#include "core/format.h"
#include "io/files.h"

namespace reel::app {
namespace {

// Text for HTML and XML: the five characters that mean something there, escaped.
std::string escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default:
        // (control characters are not allowed in XML 1.0)
        if (static_cast<unsigned char>(c) < 0x20 && c != '\n' && c != '\t') out += ' ';
        else out += c;
    }
  }
  return out;
}

std::string num(double x, int digits = 4) { return formatNumber(x, digits); }

const char* verdictWord(const FrameOutcome& o) {
  switch (o.verdict) {
    case FrameOutcome::Verdict::Pass: return "passed";
    case FrameOutcome::Verdict::Fail: return o.updated ? "updated" : "differs";
    case FrameOutcome::Verdict::Missing: return o.updated ? "written" : "no golden";
    case FrameOutcome::Verdict::Error: return "did not render";
  }
  return "";
}

// One row of the metrics table: the value, the limit, held or not.
std::string metricRow(const std::string& name, const std::string& value, const std::string& limit, bool ok) {
  return "<tr class=\"" + std::string(ok ? "ok" : "bad") + "\"><th>" + name + "</th><td>" + value + "</td><td>" + limit +
         "</td><td>" + (ok ? "✓" : "✗") + "</td></tr>";
}

std::string metricsTable(const FrameOutcome& o) {
  const Tolerance& t = o.tolerance;
  const ImageDiff& d = o.diff;
  std::string s = "<table class=\"metrics\"><tr><th>metric</th><th>value</th><th>limit</th><th></th></tr>";
  s += metricRow("mean |Δ| (0–255)", num(d.mean_abs), "≤ " + num(t.max_mean), d.mean_abs <= t.max_mean);
  s += metricRow("pixels off by more than " + std::to_string(t.threshold), num(100.0 * d.over_fraction) + "%",
                 "≤ " + num(100.0 * t.max_fraction) + "%", d.over_fraction <= t.max_fraction);
  s += metricRow("SSIM", num(o.ssim, 5), "≥ " + num(t.min_ssim, 5), o.ssim >= t.min_ssim);
  s += metricRow("FLIP (mean)", num(o.flip), "≤ " + num(t.max_flip), o.flip <= t.max_flip);
  s += "<tr class=\"info\"><th>FLIP (worst pixel)</th><td>" + num(o.flip_max) + "</td><td></td><td></td></tr>";
  s += "<tr class=\"info\"><th>largest |Δ|, PSNR</th><td>" + std::to_string(d.max_abs) + ", " +
       (std::isfinite(d.psnr_db) ? num(d.psnr_db) + " dB" : std::string("∞")) + "</td><td></td><td></td></tr>";
  return s + "</table>";
}

std::string img(const std::string& src, const std::string& alt, const std::string& cls = "") {
  return "<img src=\"" + escape(src) + "\" alt=\"" + escape(alt) + "\"" + (cls.empty() ? "" : " class=\"" + cls + "\"") + ">";
}

// A failure: its title, metrics, the three pictures side by side, and the slider and flicker
// views of expected against actual.
std::string failureCard(const FrameOutcome& o, int id) {
  const std::string title = o.test_case + ", frame " + std::to_string(o.frame);
  std::string s = "<section class=\"card fail\" id=\"c" + std::to_string(id) + "\"><h2><span class=\"badge\">" +
                  verdictWord(o) + "</span> " + escape(title) + " <small>t = " + num(o.time) + " s · " + escape(o.scene) +
                  "</small></h2>";
  if (!o.message.empty()) s += "<p class=\"msg\">" + escape(o.message) + "</p>";
  if (!o.golden.empty()) s += "<p class=\"golden\">golden: <code>" + escape(o.golden) + "</code></p>";
  if (o.verdict == FrameOutcome::Verdict::Fail && std::find(o.broken.begin(), o.broken.end(), "size") == o.broken.end())
    s += metricsTable(o);
  const bool both = !o.expected.empty() && !o.actual.empty();
  s += "<div class=\"views\">";
  if (both) {
    s += "<div class=\"tabs\"><button class=\"on\" data-view=\"side\">side by side</button><button data-view=\"slider\">slider</button>"
         "<button data-view=\"flicker\">flicker</button></div>";
  }
  s += "<div class=\"view side\">";
  if (!o.expected.empty()) s += "<figure>" + img(o.expected, "expected") + "<figcaption>expected (golden)</figcaption></figure>";
  if (!o.actual.empty()) s += "<figure>" + img(o.actual, "actual") + "<figcaption>actual</figcaption></figure>";
  if (!o.difference.empty())
    s += "<figure>" + img(o.difference, "difference") + "<figcaption>difference: FLIP over the golden in grey (purple: a little, yellow: much)</figcaption></figure>";
  s += "</div>";
  if (both) {
    s += "<div class=\"view slider\" hidden><div class=\"stack\">" + img(o.expected, "expected") +
         "<div class=\"clip\" style=\"width:50%\">" + img(o.actual, "actual") +
         "</div></div><input type=\"range\" min=\"0\" max=\"100\" value=\"50\" aria-label=\"actual on the left, expected on the right\">"
         "<p class=\"hint\">actual on the left of the line, expected on the right</p></div>";
    s += "<div class=\"view flicker\" hidden><div class=\"stack\">" + img(o.expected, "expected") +
         "<div class=\"flip-layer\">" + img(o.actual, "actual") +
         "</div></div><p class=\"hint\">showing <b class=\"which\">actual</b>, twice a second</p></div>";
  }
  s += "</div></section>\n";
  return s;
}

constexpr const char* kStyle = R"(
[hidden]{display:none!important}
body{font:14px/1.45 system-ui,sans-serif;margin:0;background:#f4f4f2;color:#222}
header{background:#1d2330;color:#eee;padding:14px 24px}header h1{margin:0;font-size:20px}
header p{margin:4px 0 0;color:#bbb}header code{background:#2c3446;color:#eee}.sum b.bad{color:#ff8a80}.sum b.ok{color:#9be59b}
main{padding:16px 24px;max-width:1400px}
.card{background:#fff;border-radius:6px;box-shadow:0 1px 3px #0002;padding:12px 16px;margin:0 0 16px}
.card.fail{border-left:5px solid #d33}.card h2{font-size:16px;margin:0 0 8px}.card h2 small{color:#777;font-weight:normal}
.badge{background:#d33;color:#fff;border-radius:3px;padding:1px 6px;font-size:12px;vertical-align:2px}
.msg{color:#a11;margin:4px 0}
table.metrics{border-collapse:collapse;margin:6px 0 10px;font-size:13px}
table.metrics th,table.metrics td{padding:2px 10px;text-align:left;border-bottom:1px solid #eee}
tr.bad td,tr.bad th{color:#c11;font-weight:600}tr.info{color:#666}
.tabs button{border:1px solid #bbb;background:#f7f7f7;padding:3px 10px;cursor:pointer;border-radius:3px;margin-right:4px}
.tabs button.on{background:#1d2330;color:#fff;border-color:#1d2330}
.view{margin-top:8px}.side{display:flex;gap:10px}
figure{margin:0}figcaption{font-size:12px;color:#555}
img{image-rendering:pixelated;display:block;max-width:100%}
.side figure{flex:1 1 0;min-width:0;max-width:480px}.side img{width:100%}
.golden{font-size:12px;color:#666;margin:0 0 6px}code{background:#eef;padding:0 3px;border-radius:2px}
.stack{position:relative;display:inline-block;line-height:0}.stack img{width:min(720px,90vw)}
.clip{position:absolute;top:0;left:0;bottom:0;overflow:hidden;border-right:2px solid #ff0}
.clip img{max-width:none}.flip-layer{position:absolute;top:0;left:0}
input[type=range]{display:block;width:min(720px,90vw);margin:6px 0}.hint{color:#666;font-size:12px;margin:2px 0}
details{background:#fff;border-radius:6px;padding:10px 16px;box-shadow:0 1px 3px #0002}
summary{cursor:pointer;font-weight:600}
.thumbs{display:flex;flex-wrap:wrap;gap:10px;margin-top:10px}
.thumbs figure{background:#fafafa;padding:4px;border:1px solid #e4e4e4;border-radius:4px}
.thumbs figcaption{max-width:180px}.all-ok{color:#275;font-weight:600}
)";

// Tabs switch the views; the slider uncovers the actual picture over the expected; the flicker
// view swaps them twice a second; #slider or #flicker in the address opens every card on that view.
// With #selftest the page checks itself: every picture decoded
// a tab shows its view alone, and a slider moves its line.
constexpr const char* kScript = R"(
document.querySelectorAll('.card').forEach(function(card){
  var tabs=card.querySelectorAll('.tabs button');
  tabs.forEach(function(b){b.addEventListener('click',function(){
    tabs.forEach(function(x){x.classList.toggle('on',x===b)});
    card.querySelectorAll('.view').forEach(function(v){v.hidden=!v.classList.contains(b.dataset.view)});
  })});
  var range=card.querySelector('input[type=range]'),clip=card.querySelector('.clip');
  if(range&&clip){
    var inner=clip.querySelector('img'),base=card.querySelector('.slider .stack > img');
    var fit=function(){inner.style.width=base.getBoundingClientRect().width+'px'};
    range.addEventListener('input',function(){clip.style.width=range.value+'%';fit()});
    window.addEventListener('resize',fit);base.addEventListener('load',fit);
  }
  var layer=card.querySelector('.flip-layer'),which=card.querySelector('.which');
  if(layer){var shown=true;setInterval(function(){shown=!shown;layer.style.visibility=shown?'visible':'hidden';
    which.textContent=shown?'actual':'expected'},500)}
});
function selftest(){
  var bad=[];
  document.querySelectorAll('img').forEach(function(i){if(!i.complete||i.naturalWidth===0)bad.push('image '+i.getAttribute('src')+' did not decode')});
  var tab=document.querySelector('.tabs button[data-view=slider]');
  if(tab){tab.click();var card=tab.closest('.card');
    if(card.querySelector('.view.side').offsetParent!==null)bad.push('the side-by-side view stays shown on the slider tab');
    if(card.querySelector('.view.slider').offsetParent===null)bad.push('the slider tab does not show the slider')}
  var r=document.querySelector('input[type=range]');
  if(r){var c=r.parentNode.querySelector('.clip');r.value=25;r.dispatchEvent(new Event('input'));
    if(c.style.width!=='25%')bad.push('the slider did not move its line ('+c.style.width+')')}
  document.body.setAttribute('data-selftest',bad.length?'fail: '+bad.join('; '):'pass');
  document.body.setAttribute('data-images',String(document.querySelectorAll('img').length));
}
if(location.hash==='#slider'||location.hash==='#flicker')
  document.querySelectorAll('.tabs button[data-view='+location.hash.slice(1)+']').forEach(function(b){b.click()});
if(location.hash==='#selftest'){if(document.readyState==='complete')selftest();else window.addEventListener('load',selftest)}
)";

}  // namespace

std::string metricsLine(const FrameOutcome& o) {
  const Tolerance& t = o.tolerance;
  const ImageDiff& d = o.diff;
  auto mark = [](bool ok) { return ok ? "" : " ✗"; };
  return "mean " + num(d.mean_abs, 3) + " (≤ " + num(t.max_mean, 3) + ")" + mark(d.mean_abs <= t.max_mean) + ", over " +
         std::to_string(t.threshold) + " " + num(100.0 * d.over_fraction, 3) + "% (≤ " + num(100.0 * t.max_fraction, 3) + "%)" +
         mark(d.over_fraction <= t.max_fraction) + ", SSIM " + num(o.ssim, 5) + " (≥ " + num(t.min_ssim, 5) + ")" +
         mark(o.ssim >= t.min_ssim) + ", FLIP " + num(o.flip, 3) + " (≤ " + num(t.max_flip, 3) + ")" + mark(o.flip <= t.max_flip);
}

Status writeHtmlReport(const std::string& dir, const TestSuite& suite, const std::vector<FrameOutcome>& outcomes) {
  std::vector<const FrameOutcome*> failed, passed;
  for (const FrameOutcome& o : outcomes) (o.passed() ? passed : failed).push_back(&o);
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>reel test: " + escape(suite.name) +
                  (failed.empty() ? " passed" : " — " + std::to_string(failed.size()) + " failed") +
                  "</title><meta name=\"viewport\" content=\"width=device-width\"><style>" + kStyle + "</style></head><body>\n";
  h += "<header><h1>reel test · " + escape(suite.name) + "</h1><p class=\"sum\">" + escape(suite.file) + " · " +
       std::to_string(outcomes.size()) + " frames: <b class=\"" + (failed.empty() ? "ok" : "bad") + "\">" +
       std::to_string(failed.size()) + " failed</b>, " + std::to_string(passed.size()) + " passed · goldens in " +
       escape(suite.goldens) + (failed.empty() ? std::string() : " · to accept every change: <code>reel test " + escape(suite.file) + " --update</code>") +
       "</p></header><main>\n";
  if (failed.empty()) h += "<p class=\"all-ok\">Every frame is within its tolerance.</p>\n";
  int id = 0;
  for (const FrameOutcome* o : failed) h += failureCard(*o, id++);
  if (!passed.empty()) {
    h += "<details><summary>" + std::to_string(passed.size()) + " passed</summary><div class=\"thumbs\">";
    for (const FrameOutcome* o : passed) {
      h += "<figure>" + (o->thumbnail.empty() ? std::string() : img(o->thumbnail, o->test_case)) + "<figcaption>" +
           escape(o->test_case) + ", frame " + std::to_string(o->frame) + "<br>" + escape(metricsLine(*o)) + "</figcaption></figure>";
    }
    h += "</div></details>\n";
  }
  h += "</main><script>" + std::string(kScript) + "</script></body></html>\n";
  io::AtomicFile f;
  if (Status st = f.open(dir + "/index.html"); !st) return st;
  if (Status st = f.write(h); !st) return st;
  return f.commit();
}

Status writeJunit(const std::string& file, const TestSuite& suite, const std::vector<FrameOutcome>& outcomes, double seconds) {
  int failures = 0, errors = 0;
  for (const FrameOutcome& o : outcomes) {
    failures += o.verdict == FrameOutcome::Verdict::Fail || o.verdict == FrameOutcome::Verdict::Missing;
    errors += o.verdict == FrameOutcome::Verdict::Error;
  }
  std::string x = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"reel test\" tests=\"" +
                  std::to_string(outcomes.size()) + "\" failures=\"" + std::to_string(failures) + "\" errors=\"" +
                  std::to_string(errors) + "\" time=\"" + num(seconds, 6) + "\">\n  <testsuite name=\"" + escape(suite.name) +
                  "\" tests=\"" + std::to_string(outcomes.size()) + "\" failures=\"" + std::to_string(failures) +
                  "\" errors=\"" + std::to_string(errors) + "\" time=\"" + num(seconds, 6) + "\">\n";
  for (const FrameOutcome& o : outcomes) {
    x += "    <testcase classname=\"" + escape(suite.name + "." + o.test_case) + "\" name=\"frame " + std::to_string(o.frame) +
         "\" file=\"" + escape(o.scene) + "\" time=\"" + num(o.seconds, 6) + "\">";
    switch (o.verdict) {
      case FrameOutcome::Verdict::Pass: break;
      case FrameOutcome::Verdict::Fail: {
        const bool sized = std::find(o.broken.begin(), o.broken.end(), "size") != o.broken.end();
        const std::string what = sized ? o.message : metricsLine(o);
        x += "\n      <failure type=\"differs\" message=\"" + escape(what) + "\">" + escape(what) + "</failure>\n    ";
        break;
      }
      case FrameOutcome::Verdict::Missing:
        x += "\n      <failure type=\"missing\" message=\"" + escape(o.message) + "\"/>\n    ";
        break;
      case FrameOutcome::Verdict::Error:
        x += "\n      <error type=\"render\" message=\"" + escape(o.message) + "\"/>\n    ";
        break;
    }
    x += "</testcase>\n";
  }
  x += "  </testsuite>\n</testsuites>\n";
  io::AtomicFile f;
  if (Status st = f.open(file); !st) return st;
  if (Status st = f.write(x); !st) return st;
  return f.commit();
}

}  // namespace reel::app
