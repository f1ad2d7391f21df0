/* The interactive site map (planner.figures.webmap): pan, zoom, layers, frames and the station panel.
   Plain ES5-level script, no library; each <div class="smap"> on the page is set up once. */
(function () {
  'use strict';
  function each(list, f) { Array.prototype.forEach.call(list, f); }
  function el(tag, text, cls) {
    var e = document.createElement(tag);
    if (text !== undefined && text !== null) e.textContent = text;
    if (cls) e.className = cls;
    return e;
  }

  function setup(root) {
    if (root.getAttribute('data-ready')) return;
    root.setAttribute('data-ready', '1');
    var svg = root.querySelector('svg.sm-svg');
    var panel = root.querySelector('.sm-panel');
    var frames = {}, stations = {}, cover = {}, floors = {}, links = {}, marks = {};
    var cur = null, view = [0, 0, 1, 1];
    each(root.querySelectorAll('.sm-fr'), function (g) {
      var f = g.getAttribute('data-frame');
      frames[f] = g;
      marks[f] = g.querySelectorAll('.sm-mk');
    });
    each(root.querySelectorAll('.sm-st'), function (s) { stations[s.getAttribute('data-id')] = s; });
    each(root.querySelectorAll('.sm-cv'), function (g) { cover[g.getAttribute('data-st')] = g; });
    each(root.querySelectorAll('.sm-fl'), function (g) { floors[g.getAttribute('data-st')] = g; });
    each(root.querySelectorAll('.sm-lk'), function (l) {
      ['data-a', 'data-b'].forEach(function (a) {
        var id = l.getAttribute(a);
        (links[id] = links[id] || []).push(l);
      });
    });

    /* metres per screen pixel (the SVG keeps its aspect: xMidYMid meet) */
    function unit() {
      var r = svg.getBoundingClientRect();
      if (!r.width || !r.height) return view[2] / 900;
      return Math.max(view[2] / r.width, view[3] / r.height);
    }
    function rescale() {
      var k = unit();
      each(marks[cur] || [], function (m) {
        m.setAttribute('transform', 'translate(' + m.getAttribute('data-x') + ',' + (-m.getAttribute('data-y')) +
          ') scale(' + k.toPrecision(4) + ')');
      });
    }
    function setView(v) {
      view = v;
      svg.setAttribute('viewBox', v.map(function (x) { return x.toFixed(3); }).join(' '));
      rescale();
    }
    function fit() { setView(frames[cur].getAttribute('data-box').split(' ').map(Number)); }
    function toUser(cx, cy) {
      var r = svg.getBoundingClientRect(), k = unit();
      var ox = r.left + (r.width - view[2] / k) / 2, oy = r.top + (r.height - view[3] / k) / 2;
      return [view[0] + (cx - ox) * k, view[1] + (cy - oy) * k];
    }
    function zoomAt(f, p) {
      var w = view[2] * f, h = view[3] * f;
      if (w < 0.05 || w > 1e7) return;
      setView([p[0] - (p[0] - view[0]) * f, p[1] - (p[1] - view[1]) * f, w, h]);
    }
    function centre() { return [view[0] + view[2] / 2, view[1] + view[3] / 2]; }
    function showFrame(f) {
      if (!frames[f]) return;
      cur = f;
      Object.keys(frames).forEach(function (g) { frames[g].style.display = g === f ? '' : 'none'; });
      var b = frames[f].getAttribute('data-box').split(' ');
      svg.style.aspectRatio = b[2] + '/' + b[3];
      var sel = root.querySelector('.sm-frame');
      if (sel) sel.value = f;
      fit();
    }

    function clear() {
      each(root.querySelectorAll('.hl'), function (e) { e.classList.remove('hl'); });
      each(root.querySelectorAll('.sm-sel,.sm-partner'), function (e) { e.classList.remove('sm-sel', 'sm-partner'); });
      each(document.querySelectorAll('tr.sm-row'), function (e) { e.classList.remove('sm-row'); });
      panel.hidden = true;
      panel.textContent = '';
    }
    function partnerButton(id, text) {
      var b = el('button', text, 'sm-go');
      b.type = 'button';
      b.setAttribute('data-go', id);
      return b;
    }
    function fill(s) {
      var d = function (a) { return s.getAttribute('data-' + a) || ''; };
      var id = d('id');
      panel.textContent = '';
      var close = el('button', '\u00d7', 'sm-close');
      close.type = 'button';
      close.title = 'close';
      close.setAttribute('data-close', '1');
      panel.appendChild(close);
      panel.appendChild(el('h3', id));
      panel.appendChild(el('p', 'x ' + d('x') + ' m, y ' + d('y') + ' m (frame ' + d('frame') + ')'));
      panel.appendChild(el('p', 'zone ' + d('zone') + ', ' + d('side') + (d('kind') ? ', ' + d('kind') : '')));
      if (cover[id] || d('n') !== '0') {
        panel.appendChild(el('p', 'covers ' + d('n') + ' wall piece(s), ' + d('m') + ' m, in ' + d('runs') + ' run(s)'));
      }
      if (d('fn')) {
        panel.appendChild(el('p', 'covers ' + d('fn') + ' floor/ceiling patch(es), ' + d('fm2') + ' m\u00b2'));
      }
      if (d('visit') && d('visit') !== '0') panel.appendChild(el('p', 'field visit no. ' + d('visit')));
      var mine = links[id] || [];
      var p = el('p', mine.length ? 'linked to: ' : 'no registration link');
      mine.forEach(function (l) {
        var other = l.getAttribute('data-a') === id ? l.getAttribute('data-b') : l.getAttribute('data-a');
        var shared = l.getAttribute('data-s');
        var how = shared ? ' (' + shared + ' m shared)' : l.getAttribute('data-o') ? ' (through an opening)' : '';
        p.appendChild(partnerButton(other, other + how));
      });
      panel.appendChild(p);
      var row = d('row') && document.getElementById(d('row'));
      if (row) {
        var a = el('a', 'row in the ' + (root.getAttribute('data-table') || 'station table'));
        a.href = '#' + d('row');
        a.setAttribute('data-row', d('row'));
        panel.appendChild(el('p')).appendChild(a);
      }
      panel.hidden = false;
      /* on a narrow screen the panel sits under the map: bring it into view */
      if (window.getComputedStyle(panel).position !== 'absolute' && panel.scrollIntoView) {
        panel.scrollIntoView({ block: 'nearest' });
      }
    }
    /* quiet: mark the station and what it covers without opening the panel (the edit mode's pick) */
    function select(id, quiet) {
      var s = stations[id];
      if (!s) return;
      clear();
      if (s.getAttribute('data-frame') !== cur) showFrame(s.getAttribute('data-frame'));
      s.classList.add('sm-sel');
      var g = cover[id];
      if (g) {
        each(g.querySelectorAll('line'), function (l) { l.classList.add('hl'); });
        g.parentNode.appendChild(g);
      }
      var f = floors[id];
      if (f) {
        each(f.querySelectorAll('path'), function (a) { a.classList.add('hl'); });
        f.parentNode.appendChild(f);
      }
      (links[id] || []).forEach(function (l) {
        l.classList.add('hl');
        var other = l.getAttribute('data-a') === id ? l.getAttribute('data-b') : l.getAttribute('data-a');
        if (stations[other]) stations[other].classList.add('sm-partner');
      });
      var row = s.getAttribute('data-row') && document.getElementById(s.getAttribute('data-row'));
      if (row) row.classList.add('sm-row');
      if (!quiet) fill(s);
    }
    root.smapSelect = function (id) { select(id); };
    /* for the edit mode (site_map_edit.js): the frame shown, its group, a quiet selection, the clearing, the station
       nearest a screen point, and a screen point in the shown frame's metres (y up: the SVG's y is turned down) through
       the inverse of the frame group's screen matrix, the same matrix the markers are drawn with */
    root.smapFrame = function () { return cur; };
    root.smapGroup = function () { return frames[cur]; };
    root.smapMark = function (id) { select(id, true); };
    root.smapClear = clear;
    root.smapToFrame = function (cx, cy) {
      var m = frames[cur] && frames[cur].getScreenCTM();
      if (!m) return null;
      var p = svg.createSVGPoint();
      p.x = cx;
      p.y = cy;
      p = p.matrixTransform(m.inverse());
      return [p.x, -p.y];
    };

    /* pan (one pointer), pinch (two); a press that moved is no click */
    var pts = {}, moved = false, downAt = null, downType = 'mouse';
    svg.addEventListener('pointerdown', function (e) {
      pts[e.pointerId] = [e.clientX, e.clientY];
      downType = e.pointerType || 'mouse';
      downAt = [e.clientX, e.clientY];
      moved = false;
    });
    svg.addEventListener('pointermove', function (e) {
      var old = pts[e.pointerId];
      if (!old) return;
      var ids = Object.keys(pts);
      if (!moved && Math.abs(e.clientX - downAt[0]) + Math.abs(e.clientY - downAt[1]) < 5 && ids.length < 2) return;
      if (!moved) {
        moved = true;
        try { svg.setPointerCapture(e.pointerId); } catch (err) { /* capture is a nicety */ }
      }
      var k = unit();
      if (ids.length === 1) {
        setView([view[0] - (e.clientX - old[0]) * k, view[1] - (e.clientY - old[1]) * k, view[2], view[3]]);
      } else if (ids.length === 2) {
        var o = pts[ids[0] === String(e.pointerId) ? ids[1] : ids[0]];
        var before = Math.hypot(old[0] - o[0], old[1] - o[1]), after = Math.hypot(e.clientX - o[0], e.clientY - o[1]);
        if (before > 0 && after > 0) zoomAt(before / after, toUser((e.clientX + o[0]) / 2, (e.clientY + o[1]) / 2));
      }
      pts[e.pointerId] = [e.clientX, e.clientY];
    });
    function up(e) { delete pts[e.pointerId]; }
    svg.addEventListener('pointerup', up);
    svg.addEventListener('pointercancel', up);
    svg.addEventListener('wheel', function (e) {
      e.preventDefault();
      var dy = e.deltaMode === 1 ? e.deltaY * 16 : e.deltaY;
      zoomAt(Math.pow(1.0015, Math.max(-300, Math.min(300, dy))), toUser(e.clientX, e.clientY));
    }, { passive: false });
    /* the station whose marker centre is nearest the screen point (cx, cy), within `radius` CSS px; null: none.
       Markers keep their screen size at every zoom, so at "fit" the hit areas of close stations overlap and the
       topmost one under a finger is often a neighbour: the nearest centre is the station meant. */
    function nearest(cx, cy, radius) {
      var best = null, bd = radius;
      each(frames[cur] ? frames[cur].querySelectorAll('.sm-st') : [], function (g) {
        if (!g.getClientRects().length) return; /* its layer is hidden */
        var m = g.getScreenCTM();
        if (!m) return;
        var d = Math.hypot(m.e - cx, m.f - cy);
        if (d <= bd) { bd = d; best = g; }
      });
      return best;
    }
    svg.addEventListener('click', function (e) {
      if (moved) { moved = false; return; }
      /* a finger (or pen) gets a wider reach than a mouse; a click made by a script (no pointer: detail 0)
         names its station by its target */
      var reach = downType === 'mouse' ? 16 : 28;
      var s = e.detail ? nearest(e.clientX, e.clientY, reach) : null;
      if (!s) s = e.target.closest ? e.target.closest('.sm-st') : null;
      /* the edit mode, where on, takes the tap (a station or a point of the map) */
      if (root.smapTap && root.smapTap(e.clientX, e.clientY, s ? s.getAttribute('data-id') : null)) return;
      if (s) select(s.getAttribute('data-id'));
      else clear();
    });
    svg.addEventListener('keydown', function (e) {
      var s = e.target.closest ? e.target.closest('.sm-st') : null;
      if (!s || (e.key !== 'Enter' && e.key !== ' ')) return;
      e.preventDefault();
      if (!(root.smapTap && root.smapTap(null, null, s.getAttribute('data-id')))) select(s.getAttribute('data-id'));
    });

    root.addEventListener('click', function (e) {
      var t = e.target.closest ? e.target.closest('button,a') : null;
      if (!t || !root.contains(t)) return;
      if (t.getAttribute('data-zoom')) {
        var z = t.getAttribute('data-zoom');
        if (z === 'fit') fit(); else zoomAt(z === 'in' ? 1 / 1.5 : 1.5, centre());
      } else if (t.getAttribute('data-go')) {
        select(t.getAttribute('data-go'));
      } else if (t.getAttribute('data-close')) {
        clear();
      } else if (t.getAttribute('data-row')) {
        var row = document.getElementById(t.getAttribute('data-row'));
        if (row) { e.preventDefault(); row.classList.add('sm-row'); row.scrollIntoView({ block: 'center' }); }
      }
    });
    each(root.querySelectorAll('input[data-layer]'), function (cb) {
      cb.addEventListener('change', function () {
        each(root.querySelectorAll('.sm-L[data-layer="' + cb.getAttribute('data-layer') + '"]'), function (g) {
          g.style.display = cb.checked ? '' : 'none';
        });
      });
    });
    var sel = root.querySelector('.sm-frame');
    if (sel) sel.addEventListener('change', function () { clear(); showFrame(sel.value); });

    /* a click on a station's row in the table shows the station on the map; a table after the map is not
       parsed yet when this runs, so the rows are bound once the document is */
    function bindRows() {
      Object.keys(stations).forEach(function (id) {
        var row = stations[id].getAttribute('data-row') && document.getElementById(stations[id].getAttribute('data-row'));
        if (!row) return;
        row.style.cursor = 'pointer';
        row.title = 'show on the site map';
        row.addEventListener('click', function () {
          select(id);
          root.scrollIntoView({ block: 'start' });
        });
      });
    }
    if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', bindRows);
    else bindRows();
    window.addEventListener('resize', rescale);
    showFrame(root.getAttribute('data-first') || Object.keys(frames)[0]);
    window.addEventListener('load', rescale);
  }

  each(document.querySelectorAll('.smap'), setup);
  document.addEventListener('DOMContentLoaded', function () { each(document.querySelectorAll('.smap'), setup); });
})();
