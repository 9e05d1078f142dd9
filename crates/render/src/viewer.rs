//! The interactive viewer (issue 16): one self-contained HTML page (no network: the picture and
//! the script are inline) around any rappel picture ([`crate::Picture`]): pan by dragging
//! and zoom with the wheel (or the + / - / fit buttons), a check box per legend layer, a picker
//! over the picture's tags (e.g. homotopy classes, [`crate::Picture::set_tag`]), and hover
//! details (the elements' `<title>` texts, e.g. anchors and poses) in a status line.
//!
//! The script marks the page when it has run (`data-viewer-ready="yes"` on `<body>`) and records
//! any script error (`data-viewer-errors`), so a headless browser can check the page
//! (`.ci/viewer-check`).

/// The viewer's script. Plain ES2015, no dependencies.
const SCRIPT: &str = r#"
(function () {
  var errors = [];
  window.addEventListener('error', function (e) {
    errors.push(String(e.message));
    document.body.setAttribute('data-viewer-errors', errors.join(' | '));
  });
  var map = document.getElementById('rappel-map');
  var panel = document.getElementById('viewer-layers');
  var picker = document.getElementById('viewer-tags');
  var status = document.getElementById('viewer-status');
  if (!map) { throw new Error('no map in the picture'); }
  var vb0 = map.getAttribute('viewBox').split(/\s+/).map(Number);
  var vb = vb0.slice();
  function apply() { map.setAttribute('viewBox', vb.join(' ')); }
  function zoom(f, cx, cy) {
    var w = vb[2] * f, h = vb[3] * f;
    vb = [cx - (cx - vb[0]) * f, cy - (cy - vb[1]) * f, w, h];
    apply();
  }
  function toMap(ev) {
    var r = map.getBoundingClientRect();
    return [vb[0] + (ev.clientX - r.left) / r.width * vb[2],
            vb[1] + (ev.clientY - r.top) / r.height * vb[3]];
  }
  map.addEventListener('wheel', function (ev) {
    ev.preventDefault();
    var p = toMap(ev);
    zoom(ev.deltaY > 0 ? 1.2 : 1 / 1.2, p[0], p[1]);
  }, { passive: false });
  var drag = null;
  map.addEventListener('mousedown', function (ev) { drag = [ev.clientX, ev.clientY, vb.slice()]; });
  window.addEventListener('mouseup', function () { drag = null; });
  window.addEventListener('mousemove', function (ev) {
    if (!drag) { return; }
    var r = map.getBoundingClientRect();
    vb = [drag[2][0] - (ev.clientX - drag[0]) / r.width * vb[2],
          drag[2][1] - (ev.clientY - drag[1]) / r.height * vb[3], vb[2], vb[3]];
    apply();
  });
  document.getElementById('viewer-zoom-in').onclick = function () { zoom(1 / 1.5, vb[0] + vb[2] / 2, vb[1] + vb[3] / 2); };
  document.getElementById('viewer-zoom-out').onclick = function () { zoom(1.5, vb[0] + vb[2] / 2, vb[1] + vb[3] / 2); };
  document.getElementById('viewer-fit').onclick = function () { vb = vb0.slice(); apply(); };
  // Layer toggles, one per legend layer.
  var names = [];
  map.querySelectorAll('g[data-layer]').forEach(function (g) {
    var n = g.getAttribute('data-layer');
    if (names.indexOf(n) < 0) { names.push(n); }
  });
  names.forEach(function (n) {
    var label = document.createElement('label');
    var box = document.createElement('input');
    box.type = 'checkbox'; box.checked = true; box.setAttribute('data-layer-toggle', n);
    box.onchange = function () {
      map.querySelectorAll('g[data-layer]').forEach(function (g) {
        if (g.getAttribute('data-layer') === n) { g.style.display = box.checked ? '' : 'none'; }
      });
    };
    label.appendChild(box);
    label.appendChild(document.createTextNode(' ' + n));
    panel.appendChild(label);
    panel.appendChild(document.createElement('br'));
  });
  // The tag picker (e.g. one homotopy class at a time).
  var tags = [];
  map.querySelectorAll('[data-tag]').forEach(function (e) {
    var t = e.getAttribute('data-tag');
    if (tags.indexOf(t) < 0) { tags.push(t); }
  });
  if (tags.length === 0) { picker.style.display = 'none'; }
  ['all'].concat(tags).forEach(function (t) {
    var o = document.createElement('option');
    o.value = t; o.textContent = t; picker.appendChild(o);
  });
  picker.onchange = function () {
    map.querySelectorAll('[data-tag]').forEach(function (e) {
      e.style.display = (picker.value === 'all' || e.getAttribute('data-tag') === picker.value) ? '' : 'none';
    });
  };
  // Hover details from the elements' titles.
  map.addEventListener('mouseover', function (ev) {
    var e = ev.target;
    while (e && e !== map) {
      var t = e.querySelector ? e.querySelector(':scope > title') : null;
      if (t) { status.textContent = t.textContent; return; }
      e = e.parentNode;
    }
  });
  document.body.setAttribute('data-viewer-layers', String(names.length));
  document.body.setAttribute('data-viewer-ready', 'yes');
})();
"#;

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The viewer page around `svg` (a rappel picture), titled `title` (module docs).
///
/// ```
/// use nalgebra::Point2;
/// use rappel_render::{Layer, Marker, Picture};
/// use rappel::geometry::polygon::Aabb;
/// let mut pic = Picture::new(Aabb { min: Point2::new(0.0, 0.0), max: Point2::new(10.0, 20.0) });
/// pic.titled_marker(Layer::Anchor, Point2::new(5.0, 10.0), "anchor 1: psi 12°");
/// let page = rappel_render::viewer::html(&pic.finish("example"), "example");
/// assert!(page.starts_with("<!DOCTYPE html>"));
/// assert!(page.contains("data-layer=\"anchor\"") && page.contains("anchor 1: psi 12°"));
/// assert!(!page.contains("http://") || page.contains("xmlns=\"http://www.w3.org/2000/svg\""));
/// ```
pub fn html(svg: &str, title: &str) -> String {
    let mut out = String::new();
    out.push_str("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
    out.push_str(&format!("<title>{}</title>\n", escape(title)));
    out.push_str(
        "<style>\nbody{margin:0;font-family:sans-serif;display:flex;height:100vh}\n\
         #viewer-side{width:230px;padding:10px;border-right:1px solid #ccc;overflow:auto;font-size:13px}\n\
         #viewer-main{flex:1;overflow:hidden;position:relative}\n\
         #viewer-main>svg{width:100%;height:100%}\n\
         #viewer-status{position:absolute;bottom:0;left:0;right:0;background:#fffe;padding:4px 8px;font-size:13px;min-height:1.2em}\n\
         button{margin-right:4px}\n</style>\n</head>\n<body>\n",
    );
    out.push_str(&format!(
        "<div id=\"viewer-side\"><b>{}</b><p><button id=\"viewer-zoom-in\">+</button>\
         <button id=\"viewer-zoom-out\">-</button><button id=\"viewer-fit\">fit</button></p>\
         <p><select id=\"viewer-tags\"></select></p><p><b>layers</b><br><span id=\"viewer-layers\"></span></p>\
         <p>drag to pan, wheel to zoom, hover for details</p></div>\n",
        escape(title)
    ));
    out.push_str("<div id=\"viewer-main\">\n");
    out.push_str(svg);
    out.push_str("<div id=\"viewer-status\"></div>\n</div>\n<script>");
    out.push_str(SCRIPT);
    out.push_str("</script>\n</body>\n</html>\n");
    out
}
