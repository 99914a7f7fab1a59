// Offline client-side search over window.SITEGEN_SEARCH (assets/search-index.js).
// Latin text is indexed by lower-cased words (matched by prefix); CJK text has no spaces between
// words, so it is indexed by overlapping character bigrams: "齒輪" is found inside "錯誤排解齒輪方向".
// Candidates from the index are then confirmed by substring match; title hits rank first.
(function () {
  "use strict";
  var docs = window.SITEGEN_SEARCH || [];
  var CJK = /[\u3040-\u30ff\u3400-\u4dbf\u4e00-\u9fff\uf900-\ufaff\uac00-\ud7af]/;
  var index = null;

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
    index = { words: {}, grams: {} };
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
      var hits = {};  // a single CJK character: any bigram containing it
      Object.keys(index.grams).forEach(function (g) {
        if (g.indexOf(tok.c) >= 0) index.grams[g].forEach(function (id) { hits[id] = 1; });
      });
      return Object.keys(hits).map(Number);
    }
    var seen = {};  // words match by prefix: "gear" finds "gears"
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
        var set = {};
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

  function filter(a, b) { var out = {}; Object.keys(a).forEach(function (k) { if (b[k]) out[k] = 1; }); return out; }
  function count(text, term) { var n = 0, at = text.indexOf(term); while (at >= 0 && n < 50) { n++; at = text.indexOf(term, at + term.length); } return n; }

  function snippet(d, terms) {
    var text = d.x, lower = text.toLowerCase(), at = -1;
    for (var i = 0; i < terms.length && at < 0; i++) at = lower.indexOf(terms[i]);
    var start = Math.max(0, at - 40), piece = text.substr(start, 160);
    return (start > 0 ? "…" : "") + piece + (start + 160 < text.length ? "…" : "");
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

  window.sitegenSearch = search;
  var input = document.getElementById("search-input");
  var list = document.getElementById("search-results");
  var status = document.getElementById("search-status");
  if (!input || !list) return;
  var root = document.querySelector('link[rel="stylesheet"]').getAttribute("href").replace(/assets\/style\.css$/, "");

  function show() {
    var q = input.value.trim(), terms = q.toLowerCase().split(/\s+/).filter(Boolean);
    list.textContent = "";
    if (!q) { status.textContent = ""; return; }
    var results = search(q);
    status.textContent = results.length ? results.length + " " + status.getAttribute("data-results") : status.getAttribute("data-none");
    results.slice(0, 50).forEach(function (r) {
      var li = document.createElement("li"), a = document.createElement("a");
      a.href = root + encodeURI(r.doc.u); a.textContent = r.doc.t;
      var where = document.createElement("div"); where.className = "where"; where.textContent = r.doc.p;
      var p = document.createElement("p"); highlight(p, snippet(r.doc, terms), terms);
      li.appendChild(a); li.appendChild(where); li.appendChild(p); list.appendChild(li);
    });
  }

  var params = new URLSearchParams(window.location.search);
  input.value = params.get("q") || "";
  input.addEventListener("input", show);
  show();
})();
