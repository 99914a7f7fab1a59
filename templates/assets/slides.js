// sitegen's slide viewer (templates/slides.html): one slide at a time, all in the page.
// Keys: Right/Left next/previous slide, Down/Up sub-slides, Space/PageDown/N and
// Shift+Space/PageUp/P step through everything in order, Home/End, F full screen,
// S notes view. Swipes on touch screens. ?notes opens the notes view, ?print the
// one-slide-per-page view. The position is kept in the address (#/2/1) so reload keeps it.
(function () {
"use strict";
var body = document.body;
var deck = document.querySelector(".deck");
if (!deck) return;
var all = Array.prototype.slice.call(deck.querySelectorAll("section.slide"));
var flat = all.map(function (el) {
return { el: el, h: +el.getAttribute("data-h"), v: +el.getAttribute("data-v") };
});
var lastH = flat.length ? flat[flat.length - 1].h : 0;
var query = location.search;
var panel = document.getElementById("notes-panel");
var counter = document.querySelector(".deck-counter");
var down = document.querySelector(".deck-down");
var bar = document.querySelector(".deck-progress span");
var cur = -1;
var started = Date.now();

function find(h, v) {
for (var i = 0; i < flat.length; i++) {
if (flat[i].h === h && flat[i].v === v) return i;
}
return -1;
}

function notesOf(i) {
var n = flat[i] && flat[i].el.querySelector(".notes");
return n ? n.innerHTML : "";
}

function titleOf(i) {
if (!flat[i]) return "";
var h = flat[i].el.querySelector("h1, h2, h3");
return h ? h.textContent.replace(/#$/, "") : "";
}

function show(i) {
if (!flat.length) return;
i = Math.max(0, Math.min(flat.length - 1, i));
if (i === cur) return;
if (cur >= 0) {
flat[cur].el.classList.remove("current");
flat[cur].el.setAttribute("aria-hidden", "true");
Array.prototype.forEach.call(flat[cur].el.querySelectorAll("video"), function (v) {
v.pause();
});
}
cur = i;
var f = flat[i];
f.el.classList.add("current");
f.el.removeAttribute("aria-hidden");
var text = (i + 1) + " / " + flat.length;
counter.textContent = text;
// Right/Left move between stacks: say on screen that this one goes on below (sub-slides)
var below = 0;
while (find(f.h, f.v + below + 1) >= 0) below++;
down.hidden = !below;
down.querySelector("b").textContent = below ? String(below) : "";
bar.style.width = (flat.length > 1 ? (100 * i) / (flat.length - 1) : 100) + "%";
body.setAttribute("data-slide", String(i));
panel.querySelector(".notes-counter").textContent = text;
panel.querySelector(".notes-body").innerHTML = notesOf(i);
panel.querySelector(".notes-next-body").textContent = titleOf(i + 1);
try {
history.replaceState(null, "", "#/" + f.h + (f.v ? "/" + f.v : ""));
} catch (e) {
// a file:// page in some browsers: the position is just not kept
}
}

function go(dh, dv) {
var f = flat[cur];
if (dh) {
var h = Math.max(0, Math.min(lastH, f.h + dh));
show(find(h, 0));
} else {
var j = find(f.h, f.v + dv);
if (j >= 0) show(j);
}
}

function notesView(on) {
body.classList.toggle("notes-mode", on);
panel.hidden = !on;
}

function fullScreen() {
var d = document;
if (d.fullscreenElement) {
d.exitFullscreen();
} else if (d.documentElement.requestFullscreen) {
d.documentElement.requestFullscreen().catch(function () {});
}
}

if (/[?&]print\b/.test(query)) {
body.classList.add("print-mode");
all.forEach(function (el) {
el.classList.add("current");
});
return;
}

document.addEventListener("keydown", function (e) {
if (e.altKey || e.ctrlKey || e.metaKey) return;
var t = e.target;
if (t && (t.tagName === "INPUT" || t.tagName === "TEXTAREA" || t.isContentEditable)) return;
var k = e.key;
if (k === "ArrowRight") go(1, 0);
else if (k === "ArrowLeft") go(-1, 0);
else if (k === "ArrowDown") go(0, 1);
else if (k === "ArrowUp") go(0, -1);
else if (k === " " || k === "PageDown" || k === "n" || k === "N") show(e.shiftKey && k === " " ? cur - 1 : cur + 1);
else if (k === "PageUp" || k === "p" || k === "P" || k === "Backspace") show(cur - 1);
else if (k === "Home") show(0);
else if (k === "End") show(flat.length - 1);
else if (k === "f" || k === "F") fullScreen();
else if (k === "s" || k === "S") notesView(!body.classList.contains("notes-mode"));
else if (k === "Escape" && body.classList.contains("notes-mode")) notesView(false);
else return;
e.preventDefault();
});

var x0 = null;
var y0 = null;
deck.addEventListener("touchstart", function (e) {
x0 = e.touches[0].clientX;
y0 = e.touches[0].clientY;
}, { passive: true });
deck.addEventListener("touchend", function (e) {
if (x0 === null) return;
var dx = e.changedTouches[0].clientX - x0;
var dy = e.changedTouches[0].clientY - y0;
x0 = null;
if (Math.max(Math.abs(dx), Math.abs(dy)) < 40) return;
if (Math.abs(dx) > Math.abs(dy)) go(dx < 0 ? 1 : -1, 0);
else go(0, dy < 0 ? 1 : -1);
});

document.querySelector(".deck-next").addEventListener("click", function () {
show(cur + 1);
});
document.querySelector(".deck-prev").addEventListener("click", function () {
show(cur - 1);
});
document.querySelector(".deck-full").addEventListener("click", fullScreen);
down.addEventListener("click", function () {
go(0, 1);
});
// Light/dark: the same choice as the site's pages (assets/site.js), remembered across both.
document.querySelector(".deck-theme").addEventListener("click", function () {
var html = document.documentElement;
var now = html.getAttribute("data-theme") ||
(matchMedia("(prefers-color-scheme: dark)").matches ? "dark" : "light");
var next = now === "dark" ? "light" : "dark";
html.setAttribute("data-theme", next);
try {
localStorage.setItem("sitegen-theme", next);
} catch (e) {
// private mode: the choice lasts for this page only
}
});
document.querySelector(".deck-notes").addEventListener("click", function () {
notesView(!body.classList.contains("notes-mode"));
});
setInterval(function () {
var s = Math.floor((Date.now() - started) / 1000);
panel.querySelector(".notes-timer").textContent =
Math.floor(s / 60) + ":" + ("0" + (s % 60)).slice(-2);
}, 1000);

all.forEach(function (el) {
el.setAttribute("aria-hidden", "true");
});
var m = /^#\/(\d+)(?:\/(\d+))?/.exec(location.hash);
var start = m ? find(+m[1], +(m[2] || 0)) : 0;
show(start < 0 ? 0 : start);
if (/[?&]notes\b/.test(query)) notesView(true);
})();
