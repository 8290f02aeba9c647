// blockworld report: the index's filters and pages (drawn from scenes.js), a scene page's
// overlay toggles. No network: everything it reads is in the site's folder.
(function () {
  'use strict';

  function hashParams() {
    var out = {};
    location.hash.replace(/^#/, '').split('&').forEach(function (kv) {
      var i = kv.indexOf('=');
      if (i > 0) out[kv.slice(0, i)] = decodeURIComponent(kv.slice(i + 1));
    });
    return out;
  }

  function setHash(p) {
    var parts = [];
    ['family', 'outcome', 'page'].forEach(function (k) {
      if (p[k]) parts.push(k + '=' + encodeURIComponent(p[k]));
    });
    location.hash = parts.join('&');
  }

  // s: [id, family, blocks, supported, outcome, kind, label, iou, thumbnail view, its width
  // and height px]
  function matches(s, family, outcome) {
    if (family && s[1] !== family) return false;
    if (!outcome) return true;
    if (outcome.indexOf('declined:') === 0) {
      return s[4] === 'declined' && s[5] === outcome.slice('declined:'.length);
    }
    return s[4] === outcome;
  }

  function thumb(s) {
    var a = document.createElement('a');
    a.className = 'thumb o-' + s[4];
    a.href = s[0] + '/index.html';
    var img = document.createElement('img');
    img.src = s[0] + '/view_' + s[8] + '.png';
    img.loading = 'lazy';
    img.width = 128;
    // Sized before it loads, so only the pictures in or near the window are fetched.
    if (s[9] > 0 && s[10] > 0) img.height = Math.round(128 * s[10] / s[9]);
    img.alt = s[0];
    var cap = document.createElement('span');
    cap.textContent = s[0] + ' · ' + s[1] + ' · ' + s[6] +
      (s[7] === null ? '' : ' · IoU ' + s[7].toFixed(3));
    a.appendChild(img);
    a.appendChild(cap);
    return a;
  }

  function pagerLinks(nav, p, page, pages) {
    nav.textContent = '';
    if (pages < 2) return;
    for (var k = 1; k <= pages; k++) {
      var a = document.createElement('a');
      a.textContent = String(k);
      a.href = '#' + ['family', 'outcome'].filter(function (f) { return p[f]; })
        .map(function (f) { return f + '=' + encodeURIComponent(p[f]); })
        .concat(['page=' + k]).join('&');
      if (k === page) a.className = 'current';
      nav.appendChild(a);
    }
  }

  function drawIndex() {
    var all = window.BLOCKWORLD_SCENES || [];
    var size = window.BLOCKWORLD_PAGE_SIZE || 200;
    var p = hashParams();
    document.getElementById('family').value = p.family || '';
    document.getElementById('outcome').value = p.outcome || '';
    var shown = all.filter(function (s) { return matches(s, p.family, p.outcome); });
    var pages = Math.max(1, Math.ceil(shown.length / size));
    var page = Math.min(Math.max(1, parseInt(p.page || '1', 10) || 1), pages);
    var grid = document.getElementById('grid');
    grid.textContent = '';
    shown.slice((page - 1) * size, page * size).forEach(function (s) {
      grid.appendChild(thumb(s));
    });
    var count = document.getElementById('count');
    count.dataset.shown = String(shown.length);
    count.textContent = shown.length + ' of ' + all.length + ' scenes' +
      (pages > 1 ? ', page ' + page + ' of ' + pages : '');
    pagerLinks(document.getElementById('pager-top'), p, page, pages);
    pagerLinks(document.getElementById('pager-bottom'), p, page, pages);
  }

  function initIndex() {
    ['family', 'outcome'].forEach(function (id) {
      document.getElementById(id).addEventListener('change', function () {
        setHash({
          family: document.getElementById('family').value,
          outcome: document.getElementById('outcome').value,
          page: ''
        });
      });
    });
    window.addEventListener('hashchange', drawIndex);
    drawIndex();
  }

  function initScene() {
    var boxes = document.querySelectorAll('input[data-overlay]');
    Array.prototype.forEach.call(boxes, function (box) {
      var sync = function () {
        document.body.classList.toggle('show-' + box.dataset.overlay, box.checked);
      };
      box.addEventListener('change', sync);
      sync();
    });
  }

  if (document.body.classList.contains('index')) initIndex();
  if (document.body.classList.contains('scene')) initScene();
})();
