// Offline client-side search over window.SITEGEN_SEARCH (assets/search-index.js).
// Latin text is indexed by lower-cased words (matched by prefix); CJK text has no spaces between
// words, so it is indexed by overlapping character bigrams: "齒輪" is found inside "錯誤排解齒輪方向".
// Candidates from the index are then confirmed by substring match; title hits rank first.
// Results are grouped by page, each with the headings (record "h") the matches fall under.
// Loaded by search.html, and on demand by site.js for the header box's result panel.
(function () {
  "use strict";
  var docs = window.SITEGEN_SEARCH || [];
  var CJK = /[\u3040-\u30ff\u3400-\u4dbf\u4e00-\u9fff\uf900-\ufaff\uac00-\ud7af]/;
  var index = null;
  // Tables keyed by words from the pages have no prototype: a page holding "constructor" or
  // "__proto__" must find its own entry, never Object.prototype's.
  function table() { return Object.create(null); }

  function tokens(text) {
    var out = [], word = "", cjk = "";
    text = text.toLowerCase();
    function flushWord() { if (word) { out.push({ w: word }); word = ""; } }
    function flushCjk() {
      if (cjk.length === 1) out.push({ c: cjk });
      for (var i = 0; i + 1 < cjk.length; i++) out.push({ c: cjk.substr(i, 2) });
      cjk = "";
    }
    for (var i = 0; i < text.length; i++) {
      var ch = text.charAt(i);
      if (CJK.test(ch)) { flushWord(); cjk += ch; }
      else if (/[0-9a-z\u00c0-\u024f]/.test(ch)) { flushCjk(); word += ch; }
      else { flushWord(); flushCjk(); }
    }
    flushWord(); flushCjk();
    return out;
  }

  function build() {
    index = { words: table(), grams: table() };
    docs.forEach(function (d, id) {
      tokens(d.t + " " + d.x).forEach(function (tok) {
        var table = tok.w ? index.words : index.grams, key = tok.w || tok.c;
        var list = table[key] || (table[key] = []);
        if (list[list.length - 1] !== id) list.push(id);
      });
    });
    index.wordKeys = Object.keys(index.words).sort();
  }

  function postings(tok) {
    if (tok.c) {
      if (tok.c.length === 2) return index.grams[tok.c] || [];
      var hits = table();  // a single CJK character: any bigram containing it
      Object.keys(index.grams).forEach(function (g) {
        if (g.indexOf(tok.c) >= 0) index.grams[g].forEach(function (id) { hits[id] = 1; });
      });
      return Object.keys(hits).map(Number);
    }
    var seen = table();  // words match by prefix: "gear" finds "gears"
    for (var i = lowerBound(index.wordKeys, tok.w); i < index.wordKeys.length && index.wordKeys[i].indexOf(tok.w) === 0; i++) {
      index.words[index.wordKeys[i]].forEach(function (id) { seen[id] = 1; });
    }
    return Object.keys(seen).map(Number);
  }

  function lowerBound(arr, x) {
    var lo = 0, hi = arr.length;
    while (lo < hi) { var mid = (lo + hi) >> 1; if (arr[mid] < x) lo = mid + 1; else hi = mid; }
    return lo;
  }

  function search(query) {
    if (!index) build();
    var terms = query.toLowerCase().split(/\s+/).filter(Boolean);
    if (!terms.length) return [];
    var candidates = null;
    terms.forEach(function (term) {
      var toks = tokens(term);
      toks.forEach(function (tok) {
        var set = table();
        postings(tok).forEach(function (id) { set[id] = 1; });
        candidates = candidates === null ? set : filter(candidates, set);
      });
    });
    if (!candidates) return [];
    var results = [];
    Object.keys(candidates).forEach(function (key) {
      var d = docs[Number(key)], title = d.t.toLowerCase(), text = d.x.toLowerCase(), score = 0;
      for (var i = 0; i < terms.length; i++) {
        var inTitle = title.indexOf(terms[i]) >= 0, at = text.indexOf(terms[i]);
        if (!inTitle && at < 0) return;
        score += (inTitle ? 100 : 0) + Math.min(count(text, terms[i]), 20);
      }
      results.push({ doc: d, score: score, id: Number(key) });
    });
    results.sort(function (a, b) { return b.score - a.score || a.id - b.id; });
    return results;
  }

  function filter(a, b) { var out = table(); Object.keys(a).forEach(function (k) { if (b[k]) out[k] = 1; }); return out; }
  function count(text, term) { var n = 0, at = text.indexOf(term); while (at >= 0 && n < 50) { n++; at = text.indexOf(term, at + term.length); } return n; }

  // Where each heading's title sits in the page text, so a match can name its section.
  function headingsOf(d) {
    if (d.ho) return d.ho;
    var lower = d.x.toLowerCase(), at = 0;
    d.ho = [];
    (d.h || []).forEach(function (h) {
      var i = lower.indexOf(h[1].toLowerCase(), at);
      if (i >= 0) { d.ho.push({ at: i, id: h[0], title: h[1] }); at = i + h[1].length; }
    });
    return d.ho;
  }

  // The sections of a page that hold the query: [{id, title, at}], the page's top first.
  function sections(d, terms, most) {
    var lower = d.x.toLowerCase(), heads = headingsOf(d), out = [], seen = table();
    for (var n = 0, at = lower.indexOf(terms[0]); at >= 0 && n < 200 && out.length < most; n++) {
      var h = null;
      for (var i = 0; i < heads.length && heads[i].at <= at; i++) h = heads[i];
      var key = h ? h.id : "";
      if (!seen[key]) { seen[key] = 1; out.push({ id: key, title: h ? h.title : "", at: at }); }
      at = lower.indexOf(terms[0], at + terms[0].length);
    }
    return out;
  }

  function snippet(text, at, width) {
    var start = Math.max(0, at - (width >> 2)), piece = text.substr(start, width);
    return (start > 0 ? "…" : "") + piece + (start + width < text.length ? "…" : "");
  }

  function highlight(el, text, terms) {
    var lower = text.toLowerCase(), i = 0;
    while (i < text.length) {
      var best = -1, len = 0;
      terms.forEach(function (t) { var at = lower.indexOf(t, i); if (at >= 0 && (best < 0 || at < best)) { best = at; len = t.length; } });
      if (best < 0) { el.appendChild(document.createTextNode(text.substr(i))); break; }
      el.appendChild(document.createTextNode(text.substring(i, best)));
      var mark = document.createElement("mark"); mark.textContent = text.substr(best, len); el.appendChild(mark);
      i = best + len;
    }
  }

  function el(tag, cls, parent) {
    var e = document.createElement(tag);
    if (cls) e.className = cls;
    if (parent) parent.appendChild(e);
    return e;
  }

  var body = document.body, root = document.documentElement.getAttribute("data-root") || "";

  // Fill `box` with results for `q`, grouped by page; `pages` caps the pages shown (the panel
  // links to the search page for the rest). Returns the number of matching pages.
  function render(box, q, pages, panel) {
    var terms = q.toLowerCase().split(/\s+/).filter(Boolean), results = search(q);
    box.textContent = "";
    if (!results.length) { el("p", "", box).textContent = body.getAttribute("data-none"); return 0; }
    results.slice(0, pages).forEach(function (r) {
      var d = r.doc, href = root + encodeURI(d.u), group = el("div", "sr-page", box);
      var title = el("a", "sr-title", group), found = sections(d, terms, panel ? 3 : 6);
      title.href = href;
      highlight(title, d.t, terms);
      if (d.p) el("small", "", title).textContent = d.p;
      found.forEach(function (s) {
        var a = s.id ? el("a", "sr-hit", group) : title;
        if (s.id) { a.href = href + "#" + encodeURIComponent(s.id); highlight(a, s.title, terms); }
        highlight(el("small", "", a), snippet(d.x, s.at, panel ? 90 : 160), terms);
      });
    });
    if (panel) {
      var more = el("a", "sr-title", el("div", "sr-page", box));
      more.href = root + "search.html?q=" + encodeURIComponent(q);
      more.textContent = body.getAttribute("data-all") + " (" + results.length + ") →";
    }
    return results.length;
  }

  window.sitegenSearch = search;
  window.sitegenResults = function (box, q, pages) { return render(box, q, pages, true); };

  // search.html: the full list, also reached by submitting the header box without JavaScript
  // having loaded the panel.
  var input = document.getElementById("search-input");
  var list = document.getElementById("search-results");
  var status = document.getElementById("search-status");
  if (!input || !list) return;

  function show() {
    var q = input.value.trim();
    list.textContent = "";
    status.textContent = "";
    if (!q) return;
    var n = render(list, q, 50, false);
    if (n) status.textContent = n + " " + body.getAttribute("data-results");
  }

  var params = new URLSearchParams(window.location.search);
  input.value = params.get("q") || "";
  input.addEventListener("input", show);
  show();
})();
