/* The field sheet's edit mode (planner.figures.webmap.edit): mark stations done, blocked or moved, draw closed areas
   and obstacles, close zones, set the crew's position and the hours left, and save edits.json (format
   planner-edits/1) as a download. Plain ES5-level script, no library, no address; it runs after site_map.js and
   reaches the map through the hooks that script sets on the map's root (smapTap, smapToFrame, smapMark, smapClear).
   Positions are the site frame's metres, rounded to the centimetre the map is written in. */
(function () {
  'use strict';
  function each(list, f) { Array.prototype.forEach.call(list, f); }
  function round(v) { return Math.round(v * 100) / 100; }
  function fmt(p) { return '(' + p[0].toFixed(2) + ', ' + p[1].toFixed(2) + ')'; }
  function cross(o, a, b) { return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]); }
  /* segments ab and cd meet (touching counts) */
  function meet(a, b, c, d) {
    var d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
    function on(p, q, r) { return Math.min(p[0], q[0]) <= r[0] && r[0] <= Math.max(p[0], q[0]) && Math.min(p[1], q[1]) <= r[1] && r[1] <= Math.max(p[1], q[1]); }
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    return (d1 === 0 && on(c, d, a)) || (d2 === 0 && on(c, d, b)) || (d3 === 0 && on(a, b, c)) || (d4 === 0 && on(a, b, d));
  }
  /* a ring the re-plan takes: some area, and no edge meeting another but its neighbours */
  function simple(poly) {
    var n = poly.length, area = 0, i, j;
    for (i = 0; i < n; i++) area += cross([0, 0], poly[i], poly[(i + 1) % n]);
    if (Math.abs(area) < 1e-9) return false;
    for (i = 0; i < n; i++) {
      for (j = i + 2; j < n; j++) {
        if (i === 0 && j === n - 1) continue;
        if (meet(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n])) return false;
      }
    }
    return true;
  }

  function setup(root) {
    var ed = root.querySelector('.sm-ed');
    if (!ed || ed.getAttribute('data-ready') || !root.smapToFrame) return;
    ed.setAttribute('data-ready', '1');
    var svg = root.querySelector('svg.sm-svg'), ns = svg.namespaceURI;
    var toggle = root.querySelector('[data-act="edit"]');
    var q = function (sel) { return ed.querySelector(sel); };
    var hint = q('.sm-ed-hint'), stRow = q('.sm-ed-st'), drawRow = q('.sm-ed-draw'), list = q('.sm-ed-list');
    var radius = q('.sm-ed-r'), note = q('.sm-ed-note'), hours = q('.sm-ed-hours'), zoneSel = q('.sm-ed-zone');
    var siteFrame = ed.getAttribute('data-site-frame');
    var key = 'planner-edits ' + document.title + ' ' + ed.getAttribute('data-key');
    var on = false, tool = 'station', picked = null, moving = false, verts = [], edits = [];
    var info = {};
    each(root.querySelectorAll('.sm-st'), function (g) {
      var d = function (a) { return g.getAttribute('data-' + a) || ''; };
      var n = d('station-number');
      info[d('id')] = {
        id: d('id'), g: g, frame: d('frame'), x: +d('x'), y: +d('y'),
        ref: n ? +n : d('station-label') || d('id'), name: n ? 'station ' + n : d('station-label') || d('id')
      };
    });

    function say(text) { hint.textContent = text; }
    function store() {
      try { window.localStorage.setItem(key, JSON.stringify({ edits: edits, hours: hours.value })); } catch (e) { /* private mode */ }
    }
    function restore() {
      try {
        var s = JSON.parse(window.localStorage.getItem(key) || 'null');
        if (s && s.edits) { edits = s.edits.filter(function (x) { return !x.st || info[x.st]; }); hours.value = s.hours || ''; }
      } catch (e) { edits = []; }
    }
    /* a screen point in the site frame's metres; null (and said why) where the frame shown is a zone's own */
    function toSite(cx, cy) {
      if (cx === null) return null;
      if (root.smapFrame() !== siteFrame) {
        say('Positions are taken in the site frame only (this is ' + root.smapFrame() + '): pick stations here.');
        return null;
      }
      var p = root.smapToFrame(cx, cy);
      return p ? [round(p[0]), round(p[1])] : null;
    }

    /* one edit per station, one crew, one per zone: a new one replaces the old */
    function put(x) {
      edits = edits.filter(function (o) {
        var same = x.t === 'crew' ? o.t === 'crew' : x.t === 'zone' ? o.t === 'zone' && o.zone === x.zone :
          x.st && o.t !== 'crew' && o.st === x.st;
        return !same;
      });
      edits.push(x);
      store();
      draw();
    }
    function text(x) {
      var s = x.st && info[x.st];
      if (x.t === 'done') return s.name + ': done' + (x.at ? ' at ' + fmt(x.at) + ' (moved)' : '');
      if (x.t === 'blocked') return s.name + ': blocked, ' + (x.r === null ? 'its tripod disc' : 'radius ' + x.r + ' m');
      if (x.t === 'area') return (x.kind === 'closed' ? 'closed area' : 'obstacle') + ', ' + x.poly.length + ' corners' + (x.note ? ': ' + x.note : '');
      if (x.t === 'zone') return 'zone ' + x.zone + ' closed';
      if (x.t === 'crew') return 'crew at ' + (x.st ? s.name : fmt(x.at));
      return '';
    }

    /* the edits file: stations by the number the sheet prints (its label where it prints none) */
    function data() {
      var out = { format: ed.getAttribute('data-format') }, st = [], areas = [], zones = [], crew = null;
      if (ed.getAttribute('data-instance')) out.plan = { instance: ed.getAttribute('data-instance') };
      edits.forEach(function (x) {
        var s = x.st && info[x.st];
        if (x.t === 'done') st.push(x.at ? { station: s.ref, status: 'done', x: x.at[0], y: x.at[1] } : { station: s.ref, status: 'done' });
        else if (x.t === 'blocked') st.push(x.r === null ? { station: s.ref, status: 'blocked' } : { station: s.ref, status: 'blocked', radius_m: x.r });
        else if (x.t === 'area') areas.push(x.note ? { kind: x.kind, polygon: x.poly, note: x.note } : { kind: x.kind, polygon: x.poly });
        else if (x.t === 'zone') zones.push(x.zone);
        else if (x.t === 'crew') crew = x.st ? { station: s.ref } : { x: x.at[0], y: x.at[1] };
      });
      if (st.length) out.stations = st;
      if (areas.length) out.areas = areas;
      if (zones.length) out.closed_zones = zones;
      if (crew) out.crew = crew;
      var h = hours.value.trim();
      if (h !== '') out.time_left_h = +h;
      return out;
    }
    root.smapEdits = data;

    function svgEl(tag, attrs, parent) {
      var e = document.createElementNS(ns, tag);
      Object.keys(attrs).forEach(function (a) { e.setAttribute(a, attrs[a]); });
      parent.appendChild(e);
      return e;
    }
    function layer(frame) {
      var fr = root.querySelector('.sm-fr[data-frame="' + frame + '"]');
      if (!fr) return null;
      var g = fr.querySelector('.sm-edo') || svgEl('g', { 'class': 'sm-edo' }, fr);
      fr.appendChild(g); /* on top */
      return g;
    }
    function dot(g, p, cls, title) {
      var d = svgEl('path', { 'class': cls, d: 'M' + p[0] + ',' + (-p[1]) + 'h0' }, g);
      if (title) svgEl('title', {}, d).textContent = title;
    }
    function pts(poly) { return poly.map(function (p) { return p[0] + ',' + (-p[1]); }).join(' '); }
    /* the marks of every edit and of the drawing under way, and the list */
    function draw() {
      each(root.querySelectorAll('.sm-edo'), function (g) { g.textContent = ''; });
      Object.keys(info).forEach(function (id) { info[id].g.classList.remove('sm-ed-done', 'sm-ed-blocked'); });
      list.textContent = '';
      edits.forEach(function (x, k) {
        var s = x.st && info[x.st], g = layer(s ? s.frame : siteFrame);
        if (s && x.t !== 'crew') s.g.classList.add(x.t === 'done' ? 'sm-ed-done' : 'sm-ed-blocked');
        if (g && x.t === 'done' && x.at) {
          svgEl('line', { 'class': 'sm-ed-move', x1: s.x, y1: -s.y, x2: x.at[0], y2: -x.at[1] }, g);
          dot(g, x.at, 'sm-ed-moved', s.name + ' stood here');
        } else if (g && x.t === 'blocked' && x.r) {
          svgEl('circle', { 'class': 'sm-ed-ring', cx: s.x, cy: -s.y, r: x.r }, g);
        } else if (g && x.t === 'area') {
          svgEl('polygon', { 'class': 'sm-ed-' + x.kind, points: pts(x.poly) }, g);
        } else if (g && x.t === 'crew') {
          dot(g, s ? [s.x, s.y] : x.at, 'sm-ed-crew', 'crew');
        }
        var li = document.createElement('li'), b = document.createElement('button');
        li.textContent = text(x);
        b.type = 'button';
        b.textContent = 'undo';
        b.setAttribute('data-undo', String(k));
        li.appendChild(b);
        list.appendChild(li);
      });
      q('.sm-ed-none').hidden = edits.length > 0;
      if (verts.length) {
        var g = layer(siteFrame);
        if (g) {
          svgEl('polyline', { 'class': 'sm-ed-draft', points: pts(verts.concat(verts.length > 2 ? [verts[0]] : [])) }, g);
          verts.forEach(function (p) { dot(g, p, 'sm-ed-dot'); });
        }
      }
      q('.sm-ed-count').textContent = verts.length + ' corner(s)';
      q('[data-act="finish"]').disabled = verts.length < 3;
    }

    function setTool(t) {
      tool = t;
      picked = null;
      moving = false;
      verts = [];
      root.smapClear();
      each(ed.querySelectorAll('[data-tool]'), function (b) { b.setAttribute('aria-pressed', String(b.getAttribute('data-tool') === t)); });
      stRow.hidden = true;
      drawRow.hidden = t !== 'closed' && t !== 'obstacle';
      say(t === 'station' ? 'Tap a station, then mark it.' : t === 'crew' ? 'Tap where the crew stands, or a station.' :
        'Tap the corners of the ' + (t === 'closed' ? 'closed area' : 'obstacle') + ', then finish.');
      draw();
    }
    function pick(id) {
      picked = id;
      moving = false;
      root.smapMark(id);
      q('.sm-ed-name').textContent = info[id].name;
      radius.value = '';
      stRow.hidden = false;
      say(info[id].name + ': done, blocked or moved?');
      if (stRow.scrollIntoView) stRow.scrollIntoView({ block: 'nearest' });
    }
    function setOn(v) {
      on = v;
      root.classList.toggle('sm-editing', v);
      toggle.setAttribute('aria-pressed', String(v));
      ed.hidden = !v;
      setTool('station');
      if (v && ed.scrollIntoView) ed.scrollIntoView({ block: 'nearest' });
    }

    /* a tap on the map while editing: (cx, cy) the screen point (null from the keyboard), id the station there */
    root.smapTap = function (cx, cy, id) {
      if (!on) return false;
      var p;
      if (tool === 'station' && moving && picked) {
        p = toSite(cx, cy);
        if (p) { put({ t: 'done', st: picked, at: p }); root.smapClear(); stRow.hidden = true; moving = false; say(text(edits[edits.length - 1]) + '. Tap a station.'); }
      } else if (tool === 'station') {
        if (id) pick(id);
        else { picked = null; root.smapClear(); stRow.hidden = true; say('Tap a station, then mark it.'); }
      } else if (tool === 'crew') {
        p = id ? null : toSite(cx, cy);
        if (id || p) { put(id ? { t: 'crew', st: id } : { t: 'crew', at: p }); say(text(edits[edits.length - 1]) + '.'); }
      } else if ((p = toSite(cx, cy))) {
        var last = verts[verts.length - 1];
        if (!last || last[0] !== p[0] || last[1] !== p[1]) verts.push(p); /* a double tap is one corner */
        draw();
      }
      return true;
    };

    function act(a, b) {
      var s = picked && info[picked];
      if (a === 'edit') setOn(!on);
      else if (b.getAttribute('data-tool')) setTool(b.getAttribute('data-tool'));
      else if (a === 'done' && s) { put({ t: 'done', st: picked }); say(text(edits[edits.length - 1]) + '. Tap a station.'); }
      else if (a === 'blocked' && s) {
        var r = radius.value.trim();
        if ((radius.validity && radius.validity.badInput) || (r !== '' && !(+r >= 0))) { say('The radius must be a number of metres, 0 or more (blank: the tripod disc).'); return; }
        put({ t: 'blocked', st: picked, r: r === '' ? null : +r });
        say(text(edits[edits.length - 1]) + '. Tap a station.');
      } else if (a === 'moved' && s) {
        if (s.frame !== siteFrame) { say(s.name + ' is drawn in ' + s.frame + ': positions are taken in the site frame only.'); return; }
        moving = true;
        say('Tap the map where ' + s.name + ' really stood.');
      } else if (a === 'crew-here' && s) { put({ t: 'crew', st: picked }); say(text(edits[edits.length - 1]) + '.'); }
      else if (a === 'finish' && verts.length >= 3 && !simple(verts)) {
        say('The outline crosses or touches itself: undo a corner, or tap the corners in order round the area.');
      } else if (a === 'finish' && verts.length >= 3) {
        put({ t: 'area', kind: tool, poly: verts, note: note.value.trim() });
        verts = [];
        note.value = '';
        draw();
        say(text(edits[edits.length - 1]) + '. Tap the corners of the next one, or pick another tool.');
      } else if (a === 'drop-vertex') { verts.pop(); draw(); }
      else if (a === 'cancel') { verts = []; draw(); }
      else if (a === 'zone' && zoneSel) { put({ t: 'zone', zone: zoneSel.value }); say(text(edits[edits.length - 1]) + '.'); }
      else if (a === 'undo' && edits.length) { edits.pop(); store(); draw(); say('Undone.'); }
      else if (a === 'save') save();
    }
    function save() {
      var h = hours.value.trim();
      if ((hours.validity && hours.validity.badInput) || (h !== '' && !(+h > 0))) { say('Hours left must be a number over 0 (blank: no limit today).'); return; }
      var blob = new Blob([JSON.stringify(data(), null, 2) + '\n'], { type: 'application/json' });
      var url = URL.createObjectURL(blob), a = document.createElement('a');
      a.href = url;
      a.download = 'edits.json';
      a.style.display = 'none';
      document.body.appendChild(a);
      a.click();
      setTimeout(function () { URL.revokeObjectURL(url); a.parentNode.removeChild(a); }, 2000);
      say('Saved edits.json (' + edits.length + ' edit(s)): planner replan plan.json edits.json --out DIR');
    }
    root.addEventListener('click', function (e) {
      var b = e.target.closest ? e.target.closest('button') : null;
      if (!b || !root.contains(b)) return;
      if (b.getAttribute('data-undo') !== null) {
        edits.splice(+b.getAttribute('data-undo'), 1);
        store();
        draw();
        say('Undone.');
      } else if (b.getAttribute('data-act') || b.getAttribute('data-tool')) {
        act(b.getAttribute('data-act'), b);
      }
    });
    hours.addEventListener('change', store);
    restore();
    draw();
  }

  each(document.querySelectorAll('.smap'), setup);
  document.addEventListener('DOMContentLoaded', function () { each(document.querySelectorAll('.smap'), setup); });
})();
