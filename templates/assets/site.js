// The reader's conveniences. Each is optional: without JavaScript the site still reads, the menu
// links to every section, and the header search box submits to search.html. Nothing here fetches:
// data comes as <script> files (assets/nav.js, assets/search-index.js), which load from file://.
(function () {
  "use strict";
  var d = document, html = d.documentElement, body = d.body, root = html.getAttribute("data-root") || "";
  function $(s, el) { return (el || d).querySelector(s); }
  function all(s, el) { return Array.prototype.slice.call((el || d).querySelectorAll(s)); }
  var loads = Object.create(null);
  function need(src, done) {  // load assets/<src> once, then call done
    var l = loads[src];
    if (l === true) return done();
    if (l) return l.push(done);
    l = loads[src] = [done];
    var s = d.createElement("script");
    s.src = root + "assets/" + src;
    s.onload = function () { loads[src] = true; l.forEach(function (f) { f(); }); };
    d.head.appendChild(s);
  }
  function on(el, type, f) { if (el) el.addEventListener(type, f); }

  // Light/dark: overrides the system setting, remembered across pages (read early in <head>).
  var themeButton = $(".theme-toggle");
  if (themeButton) {
    themeButton.hidden = false;
    on(themeButton, "click", function () {
      var now = html.getAttribute("data-theme") ||
        (matchMedia("(prefers-color-scheme: dark)").matches ? "dark" : "light");
      var next = now === "dark" ? "light" : "dark";
      html.setAttribute("data-theme", next);
      try { localStorage.setItem("sitegen-theme", next); } catch (e) { /* private mode */ }
    });
  }

  // Phone menu: a drawer that closes with its button, Esc, or a tap beside it.
  var toggle = $(".menu-toggle"), nav = d.getElementById("nav");
  function menu(open, refocus) {
    nav.classList.toggle("shown", open);
    body.classList.toggle("menu-open", open);
    toggle.setAttribute("aria-expanded", open ? "true" : "false");
    if (open) ($("li.current > a", nav) || $("a", nav)).focus();
    else if (refocus) toggle.focus();
  }
  if (toggle && nav) {
    on(toggle, "click", function () { menu(!nav.classList.contains("shown")); });
    on($(".menu-close button"), "click", function () { menu(false, true); });
    on(d, "click", function (e) {
      if (nav.classList.contains("shown") && !nav.contains(e.target) && !toggle.contains(e.target)) menu(false);
    });
    on(d, "keydown", function (e) {
      if (e.key === "Escape" && nav.classList.contains("shown")) menu(false, true);
    });
  }

  // Menu sections fold in place. The open branch is in the page; other sections are filled from
  // assets/nav.js on their first expand, so a page never carries the whole site's menu.
  var byUrl = null;
  function fill(items) { items.forEach(function (n) { byUrl[n[1]] = n[2]; fill(n[2]); }); }
  function foldButton(li) {
    var b = d.createElement("button"), sub = $(":scope > ul", li);
    b.type = "button";
    b.className = "fold";
    b.setAttribute("aria-label", li.firstElementChild.textContent);
    b.setAttribute("aria-expanded", sub ? "true" : "false");
    li.insertBefore(b, li.firstElementChild.nextSibling);
    on(b, "click", function () {
      var ul = $(":scope > ul", li);
      if (ul) {
        ul.hidden = !ul.hidden;
        return b.setAttribute("aria-expanded", ul.hidden ? "false" : "true");
      }
      need("nav.js", function () {
        if ($(":scope > ul", li)) return;
        if (!byUrl) { byUrl = Object.create(null); fill(window.SITEGEN_NAV || []); }
        ul = d.createElement("ul");
        (byUrl[li.getAttribute("data-s")] || []).forEach(function (n) {
          var c = d.createElement("li"), a = d.createElement("a");
          a.href = root + encodeURI(n[1]);
          a.textContent = n[0];
          c.appendChild(a);
          if (n[2].length) { c.setAttribute("data-s", n[1]); foldButton(c); }
          ul.appendChild(c);
        });
        li.appendChild(ul);
        b.setAttribute("aria-expanded", "true");
      });
    });
  }
  all("#nav li[data-s]").forEach(foldButton);

  // On this page: mark the heading being read -- the last one scrolled past the top bar; near
  // the end of the page, where the last sections cannot reach the top, the heading the reader
  // jumped to (the address's #id) or else the last one in view.
  function byId(hash) {  // "#id" as written in a link or percent-encoded in the address
    try { return d.getElementById(decodeURIComponent(hash.slice(1))); } catch (e) { return d.getElementById(hash.slice(1)); }
  }
  var tocLinks = all(".toc a"), heads = tocLinks.map(function (a) {
    return byId(a.getAttribute("href"));
  }), ticking = false;
  function mark() {
    ticking = false;
    var top = $(".topbar").offsetHeight + 24, at = 0, view = window.innerHeight;
    heads.forEach(function (h, i) { if (h && h.getBoundingClientRect().top <= top) at = i; });
    var end = window.scrollY + view >= d.documentElement.scrollHeight - 4;
    var jumped = location.hash ? heads.indexOf(byId(location.hash)) : -1;
    if (jumped > at && heads[jumped].getBoundingClientRect().top < view) at = jumped;
    else if (end && jumped < 0) {
      heads.forEach(function (h, i) { if (h && i > at && h.getBoundingClientRect().top < view) at = i; });
    }
    tocLinks.forEach(function (a, i) { a.classList.toggle("active", i === at); });
  }
  if (tocLinks.length) {
    on(window, "scroll", function () { if (!ticking) { ticking = true; requestAnimationFrame(mark); } });
    on(window, "hashchange", mark);
    mark();
  }

  // A copy button on every code block; the clipboard API where allowed, else a selection copy.
  function copy(text, done) {
    function fallback() {
      var t = d.createElement("textarea");
      t.value = text;
      t.setAttribute("readonly", "");
      t.style.cssText = "position:fixed;top:0;opacity:0";
      body.appendChild(t);
      t.select();
      try { if (d.execCommand("copy")) done(); } catch (e) { /* nothing to do */ }
      body.removeChild(t);
    }
    if (navigator.clipboard && window.isSecureContext) navigator.clipboard.writeText(text).then(done, fallback);
    else fallback();
  }
  all(".body pre").forEach(function (pre) {
    var box = pre.closest(".highlight");
    if (!box) {
      box = d.createElement("div");
      box.className = "highlight";
      pre.parentNode.insertBefore(box, pre);
      box.appendChild(pre);
    }
    if ($(".copy", box)) return;
    var b = d.createElement("button"), label = body.getAttribute("data-copy");
    b.type = "button";
    b.className = "copy";
    b.textContent = label;
    on(b, "click", function () {
      var code = $(".code pre", box) || $("pre", box);
      copy(code.textContent.replace(/\n$/, ""), function () {
        b.textContent = body.getAttribute("data-copied");
        b.focus();
        setTimeout(function () { b.textContent = label; }, 1500);
      });
    });
    box.insertBefore(b, box.firstChild);
  });

  // Code and tables wider than the page scroll sideways in their box: such a box takes the
  // keyboard focus (Tab to it, then the arrow keys scroll), as long as it scrolls.
  var resizing = false;
  function scrollables() {
    resizing = false;
    all(".body pre, .body table").forEach(function (el) {
      if (el.scrollWidth > el.clientWidth + 1) {
        if (!el.hasAttribute("tabindex")) el.setAttribute("tabindex", "0");
      } else if (el.getAttribute("tabindex") === "0") el.removeAttribute("tabindex");
    });
  }
  scrollables();
  on(window, "resize", function () { if (!resizing) { resizing = true; requestAnimationFrame(scrollables); } });

  // Search as you type in the header box: "/" focuses it, arrows move, Enter opens, Esc closes.
  var input = $(".search-box input"), panel = d.getElementById("search-panel"), active = -1;
  if (!input || !panel) return;
  input.setAttribute("role", "combobox");
  input.setAttribute("aria-controls", "search-panel");
  input.setAttribute("aria-expanded", "false");
  panel.setAttribute("role", "listbox");
  function options() { return all("a", panel); }
  function select(i) {  // i < 0: none
    var opts = options();
    active = opts.length && i >= 0 ? i % opts.length : -1;
    opts.forEach(function (a, j) { a.setAttribute("aria-selected", j === active ? "true" : "false"); });
    if (active >= 0) {
      input.setAttribute("aria-activedescendant", opts[active].id);
      opts[active].scrollIntoView({ block: "nearest" });
    } else input.removeAttribute("aria-activedescendant");
  }
  function show(open) {
    panel.hidden = !open;
    input.setAttribute("aria-expanded", open ? "true" : "false");
  }
  function run() {
    var q = input.value.trim();
    if (!q) return show(false);
    need("search-index.js", function () {
      need("search.js", function () {
        if (input.value.trim() !== q) return;
        window.sitegenResults(panel, q, 8);
        options().forEach(function (a, i) { a.id = "sr-" + i; a.setAttribute("role", "option"); });
        select(-1);
        show(true);
      });
    });
  }
  on(input, "input", run);
  on(input, "focus", function () { need("search-index.js", function () { need("search.js", function () {}); }); run(); });
  on(input, "keydown", function (e) {
    if (e.key === "ArrowDown" || e.key === "ArrowUp") {
      e.preventDefault();
      if (panel.hidden) run();
      var n = options().length;
      select(e.key === "ArrowDown" ? active + 1 : (active <= 0 ? n : active) - 1);
    } else if (e.key === "Enter" && active >= 0 && !panel.hidden) {
      e.preventDefault();
      location.href = options()[active].href;
    } else if (e.key === "Escape") {
      if (!panel.hidden) { e.preventDefault(); show(false); } else input.blur();
    }
  });
  on(d, "keydown", function (e) {
    var t = e.target, tag = t.tagName;
    if (e.key === "/" && !e.ctrlKey && !e.metaKey && !e.altKey && tag !== "INPUT" && tag !== "TEXTAREA" &&
        tag !== "SELECT" && !t.isContentEditable) {
      e.preventDefault();
      input.focus();
      input.select();
    }
  });
  on(d, "click", function (e) { if (!input.form.contains(e.target)) show(false); });
})();
