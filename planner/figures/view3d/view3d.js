/* The 3-D view of report.html: walls, floors, ceilings and stations drawn on a canvas (2D context) with an
   orthographic projection and the painter's algorithm; drag to rotate, wheel or buttons to zoom, a storey filter,
   a station list (or a click on a station) to highlight the wall it covers. No library, no address: the scene is
   the JSON of the application/json script element of class v3-data beside this script. */
(function () {
  'use strict';
  var D2R = Math.PI / 180;
  function init(root) {
    if (root.v3dReady) return;
    root.v3dReady = true;
    var data = JSON.parse(root.querySelector('.v3-data').textContent);
    var canvas = root.querySelector('canvas'), ctx = canvas.getContext('2d');
    var viewSel = root.querySelector('.v3-view'), stSel = root.querySelector('.v3-station');
    var ceilBox = root.querySelector('.v3-ceil'), info = root.querySelector('.v3-info');
    var walls = data.walls, stations = data.stations, zones = data.zones;
    var st = { yaw: -35, pitch: 35, zoom: 1, view: 0, sel: -1, shown: {} };
    var box = null, placed = [];

    function opt(sel, value, text) {
      var o = document.createElement('option'); o.value = value; o.textContent = text; sel.appendChild(o);
    }
    data.views.forEach(function (v, k) { opt(viewSel, k, v[0]); });
    if (data.views.length < 2) viewSel.parentNode.hidden = true;
    opt(stSel, -1, 'all stations: the wall they cover');
    stations.forEach(function (s, k) { opt(stSel, k, s[1] + ': ' + s[0]); });

    function setView(k) {
      st.view = k; st.shown = {};
      data.views[k][1].forEach(function (z) { st.shown[z] = true; });
      var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
      function grow(x, y, z) {
        var p = [x, y, z];
        for (var i = 0; i < 3; i++) { if (p[i] < lo[i]) lo[i] = p[i]; if (p[i] > hi[i]) hi[i] = p[i]; }
      }
      walls.forEach(function (w) {
        if (!st.shown[w[0]]) return;
        grow(w[2], w[3], w[6]); grow(w[4], w[5], Math.max(w[7], w[8]));
      });
      stations.forEach(function (s) { if (st.shown[s[2]]) grow(s[3], s[4], s[6]); });
      if (lo[0] === Infinity) { lo = [-1, -1, 0]; hi = [1, 1, 1]; }
      box = { c: [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2],
              d: Math.max(Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]), 1) };
      viewSel.value = String(k);
    }

    function camera(w, h) {
      var cy = Math.cos(st.yaw * D2R), sy = Math.sin(st.yaw * D2R);
      var cp = Math.cos(st.pitch * D2R), sp = Math.sin(st.pitch * D2R);
      var s = 0.92 * Math.min(w, h) / box.d * st.zoom, c = box.c;
      return function (x, y, z) {  /* -> [px, py, depth (larger: farther)] */
        var dx = x - c[0], dy = y - c[1], dz = z - c[2];
        var x1 = dx * cy - dy * sy, y1 = dx * sy + dy * cy;
        return [w / 2 + s * x1, h / 2 - s * (y1 * sp + dz * cp), y1 * cp - dz * sp];
      };
    }

    function quad(w, s0, s1) {  /* the part of wall w from s0 to s1 (m along it) as four world points */
      var n = Math.hypot(w[4] - w[2], w[5] - w[3]) || 1, out = [];
      [[s0, 0], [s1, 0], [s1, 1], [s0, 1]].forEach(function (q) {
        var t = q[0] / n, x = w[2] + t * (w[4] - w[2]), y = w[3] + t * (w[5] - w[3]);
        out.push([x, y, q[1] ? w[7] + t * (w[8] - w[7]) : w[6]]);
      });
      return out;
    }

    function path(pts) {
      ctx.moveTo(pts[0][0], pts[0][1]);
      for (var i = 1; i < pts.length; i++) ctx.lineTo(pts[i][0], pts[i][1]);
      ctx.closePath();
    }

    function draw() {
      var dpr = window.devicePixelRatio || 1, w = canvas.clientWidth || 900, h = canvas.clientHeight || 560;
      if (canvas.width !== Math.round(w * dpr) || canvas.height !== Math.round(h * dpr)) {
        canvas.width = Math.round(w * dpr); canvas.height = Math.round(h * dpr);
      }
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      ctx.fillStyle = '#fbfbf8'; ctx.fillRect(0, 0, w, h);
      var P = camera(w, h), items = [], drawn = 0;
      data.surfaces.forEach(function (f) {  /* floors first, filled; ceilings last, outlined */
        if (!st.shown[f[0]] || (f[1] === 'c' && !ceilBox.checked)) return;
        var rings = f[3].map(function (r) {
          var pts = [];
          for (var i = 0; i < r.length; i += 2) pts.push(P(r[i], r[i + 1], f[2]));
          return pts;
        });
        var d = 0; rings[0].forEach(function (p) { d += p[2]; });
        items.push({ key: f[1] === 'f' ? 1e12 : -1e12, d: d, rings: rings, kind: f[1] });
      });
      var cover = st.sel >= 0 ? stations[st.sel][7] : data.covered, onWall = {};
      cover.forEach(function (c) { (onWall[c[0]] = onWall[c[0]] || []).push(c); });
      walls.forEach(function (w, k) {
        if (!st.shown[w[0]]) return;
        var pts = quad(w, 0, Math.hypot(w[4] - w[2], w[5] - w[3])).map(function (p) { return P(p[0], p[1], p[2]); });
        var d = (pts[0][2] + pts[1][2] + pts[2][2] + pts[3][2]) / 4;
        items.push({ key: d, d: d, rings: [pts], kind: 'w' });
        (onWall[k] || []).forEach(function (c) {
          var q = quad(w, c[1], c[2]).map(function (p) { return P(p[0], p[1], p[2]); });
          items.push({ key: d - 1e-9, d: d, rings: [q], kind: 'v' });
        });
      });
      items.sort(function (a, b) { return b.key - a.key; });
      var style = {
        f: ['rgba(205,200,185,0.55)', 'rgba(120,110,90,0.5)'], c: [null, 'rgba(120,60,160,0.55)'],
        w: ['rgba(170,178,190,0.42)', 'rgba(60,66,80,0.8)'], v: ['rgba(40,170,70,0.62)', 'rgba(20,110,40,0.9)']
      };
      items.forEach(function (it) {
        var s = style[it.kind];
        ctx.beginPath(); it.rings.forEach(path);
        if (s[0]) { ctx.fillStyle = s[0]; ctx.fill('evenodd'); }
        ctx.setLineDash(it.kind === 'c' ? [5, 4] : []);
        ctx.strokeStyle = s[1]; ctx.lineWidth = it.kind === 'v' ? 1 : 0.8; ctx.stroke();
        drawn++;
      });
      ctx.setLineDash([]);
      placed = [];
      stations.forEach(function (s, k) {
        if (!st.shown[s[2]]) return;
        var top = P(s[3], s[4], s[6]), foot = P(s[3], s[4], s[5]), on = k === st.sel;
        ctx.beginPath(); ctx.moveTo(foot[0], foot[1]); ctx.lineTo(top[0], top[1]);
        ctx.strokeStyle = '#333'; ctx.lineWidth = 1; ctx.stroke();
        ctx.beginPath(); ctx.arc(top[0], top[1], on ? 7 : 5, 0, 2 * Math.PI);
        ctx.fillStyle = on ? '#d01c1c' : '#1f4fbf'; ctx.fill();
        ctx.strokeStyle = '#fff'; ctx.lineWidth = 1.5; ctx.stroke();
        ctx.fillStyle = '#111'; ctx.font = (on ? 'bold ' : '') + '12px system-ui,sans-serif';
        ctx.fillText(s[1], top[0] + 8, top[1] - 7);
        placed.push([k, top[0], top[1]]);
        drawn++;
      });
      canvas.setAttribute('data-drawn', drawn);
    }

    function report() {
      var cover = st.sel >= 0 ? stations[st.sel][7] : data.covered, n = 0;
      cover.forEach(function (c) { n += c[3]; });
      var what = st.sel >= 0
        ? 'Station ' + stations[st.sel][1] + ' (' + stations[st.sel][0] + ', ' + zones[stations[st.sel][2]][0] +
          '): covers ' + n + ' wall pieces in ' + cover.length + ' runs (green).'
        : 'All stations: ' + n + ' wall pieces covered (green); pick a station to see its own.';
      info.textContent = what;
      info.setAttribute('data-pieces', n);
      info.setAttribute('data-station', st.sel >= 0 ? stations[st.sel][0] : '');
    }

    function select(k) {
      st.sel = k;
      if (k >= 0 && !st.shown[stations[k][2]]) {  /* show a storey that holds it */
        for (var v = 0; v < data.views.length; v++) {
          if (data.views[v][1].indexOf(stations[k][2]) >= 0) { setView(v); break; }
        }
      }
      stSel.value = String(k);
      report(); draw();
    }

    viewSel.addEventListener('change', function () { setView(+viewSel.value); draw(); });
    stSel.addEventListener('change', function () { select(+stSel.value); });
    ceilBox.addEventListener('change', draw);
    root.querySelectorAll('button[data-v3]').forEach(function (b) {
      b.addEventListener('click', function () {
        var a = b.getAttribute('data-v3');
        if (a === 'in') st.zoom *= 1.25; else if (a === 'out') st.zoom /= 1.25;
        else if (a === 'top') { st.pitch = 90; st.yaw = 0; }
        else { st.zoom = 1; st.yaw = -35; st.pitch = 35; }
        draw();
      });
    });
    var pending = false;
    function later() {  /* one redraw per animation frame while dragging or wheeling */
      if (pending) return;
      pending = true;
      (window.requestAnimationFrame || setTimeout)(function () { pending = false; draw(); });
    }
    var drag = null;
    canvas.addEventListener('pointerdown', function (e) {
      drag = { x: e.clientX, y: e.clientY, yaw: st.yaw, pitch: st.pitch, moved: false };
      try { canvas.setPointerCapture(e.pointerId); } catch (err) { /* a synthetic pointer: no capture */ }
    });
    canvas.addEventListener('pointermove', function (e) {
      if (!drag) return;
      var dx = e.clientX - drag.x, dy = e.clientY - drag.y;
      if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
      st.yaw = drag.yaw - dx * 0.4;
      st.pitch = Math.max(0, Math.min(90, drag.pitch + dy * 0.4));
      later();
    });
    canvas.addEventListener('pointerup', function (e) {
      if (drag && !drag.moved) {
        var r = canvas.getBoundingClientRect(), x = e.clientX - r.left, y = e.clientY - r.top, best = -1, bd = 14;
        placed.forEach(function (p) { var d = Math.hypot(p[1] - x, p[2] - y); if (d < bd) { bd = d; best = p[0]; } });
        if (best >= 0) select(best === st.sel ? -1 : best);
      }
      drag = null;
    });
    canvas.addEventListener('wheel', function (e) {
      e.preventDefault();
      st.zoom *= e.deltaY < 0 ? 1.15 : 1 / 1.15;
      later();
    }, { passive: false });
    window.addEventListener('resize', later);
    root.v3dSelect = function (id) {
      for (var k = 0; k < stations.length; k++) if (stations[k][0] === id) return select(k);
      select(-1);
    };
    root.v3dState = st;
    root.v3dPlaced = function () { return placed.slice(); };  /* [station, px, py] as last drawn */
    setView(0); report(); draw();
  }
  function all() { document.querySelectorAll('.v3d').forEach(init); }
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', all); else all();
})();
