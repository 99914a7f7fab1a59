/* sitegen replay viewer: plays a clip's glTF replay (sims/replay/) in its figure.
 *
 * Markup: templates/partials/clip.html (figure.clip-replay with the poster, the control bar and
 * the time plot). This script is loaded only on pages with a replay. Everything it loads is a
 * classic <script> or, over http(s) only, a fetch() of the clip's .glb; never an ES module, so
 * a site opened from file:// works too: three.js (assets/replay/three.min.js,
 * window.SITEGEN_THREE) and, from disk, each clip's replay.js, which calls
 * window.sitegenReplay(itsScriptElement, base64Glb).
 *
 * A replay starts when its figure comes near the viewport; without WebGL 2 the poster stays,
 * and a reader who prefers reduced motion sees the poster until pressing play (no autoplay).
 * Time is simulated time; the speed selector scales it (0.25x-4x, and the clip's own speed).
 * Tests and benches read figure.sitegenReplay (seek, time, pose, screen) and
 * figure.dataset.state ("poster", "loading", "ready", "no-webgl", "failed").
 */
(function () {
  "use strict";
  if (window.sitegenReplay) return;
  var waiting = new Map(); // replay.js script element -> resolve(base64)
  window.sitegenReplay = function (script, data) {
    var done = waiting.get(script);
    if (done) { waiting.delete(script); done(data); }
  };
  var threeLoad = null;
  var reduced = window.matchMedia && matchMedia("(prefers-reduced-motion: reduce)").matches;

  function addScript(src, onload, onerror) {
    var s = document.createElement("script");
    s.async = true;
    s.onload = onload;
    s.onerror = function () { onerror(new Error("could not load " + src)); };
    s.src = src;
    return s;
  }
  function loadThree(src) {
    threeLoad = threeLoad || new Promise(function (resolve, reject) {
      document.head.appendChild(addScript(src, function () { resolve(window.SITEGEN_THREE); }, reject));
    });
    return threeLoad;
  }
  function loadData(src, glb) {
    if (glb && /^https?:$/.test(location.protocol) && window.fetch) {
      // served: the .glb itself (a quarter smaller than its base64 script, nothing to decode)
      return fetch(glb).then(function (r) {
        if (!r.ok) throw new Error(glb + ": " + r.status);
        return r.arrayBuffer();
      }).catch(function () { return loadData(src); }); // a server refusing .glb: the script
    }
    return new Promise(function (resolve, reject) {
      var s = addScript(src, function () {
        if (waiting.has(s)) { waiting.delete(s); reject(new Error(src + " held no replay")); }
      }, reject);
      waiting.set(s, resolve);
      document.head.appendChild(s);
    });
  }
  function mark(name) { if (window.performance && performance.mark) performance.mark(name); }
  function decode(b64) {
    var bin = atob(b64), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return bytes.buffer;
  }
  function hasWebGL() {
    try {
      var gl = document.createElement("canvas").getContext("webgl2");
      var lose = gl && gl.getExtension("WEBGL_lose_context");
      if (lose) lose.loseContext();
      return !!gl;
    } catch (e) { return false; }
  }

  function Viewer(fig) {
    this.fig = fig;
    this.stage = fig.querySelector(".replay-stage");
    this.bar = fig.querySelector(".replay-bar");
    this.play = fig.querySelector(".replay-play");
    this.slider = fig.querySelector(".replay-time");
    this.clock = fig.querySelector(".replay-clock");
    this.speedBox = fig.querySelector(".replay-speed");
    this.plot = fig.querySelector("svg.plot-svg[data-t-end]");
    this.cursor = this.plot && this.plot.querySelector(".plot-cursor");
    this.duration = parseFloat(fig.dataset.duration) || 0;
    this.unit = fig.dataset.unit || "s";
    this.t = 0;
    this.speed = parseFloat(this.speedBox.value) || 1;
    this.playing = false;
    this.started = false;
    this.frames = 0;
    fig.dataset.state = "poster";
    fig.sitegenReplay = this.api();
    this.bar.hidden = false;
    this.bind();
    this.show();
  }

  Viewer.prototype.api = function () {
    var v = this;
    return {
      seek: function (t) { v.seek(t); v.draw(); },
      get time() { return v.t; },
      get duration() { return v.duration; },
      get clipDuration() { return v.action ? v.action.getClip().duration : 0; },
      get moving() { // the names of the nodes the animation moves: the robot's links
        var names = v.action ? v.action.getClip().tracks.map(function (t) { return t.name.split(".")[0]; }) : [];
        return names.filter(function (n, i) { return names.indexOf(n) === i; });
      },
      get frames() { return v.frames; },
      get playing() { return v.playing; },
      pause: function () { v.setPlaying(false); },
      pose: function (name) { return v.pose(name); },
      screen: function (name) { return v.screen(name); },
      orbit: function (radians) { v.orbit(radians); },
      show: function (name, on) { v.showObject(name, on); }
    };
  };

  Viewer.prototype.bind = function () {
    var v = this;
    this.play.addEventListener("click", function () { v.toggle(); });
    this.slider.addEventListener("input", function () {
      var t = parseFloat(v.slider.value);
      v.start(false);
      v.setPlaying(false);
      v.seek(t);
      v.draw();
    });
    this.speedBox.addEventListener("change", function () { v.speed = parseFloat(v.speedBox.value) || 1; });
    this.fig.querySelector(".replay-reset").addEventListener("click", function () { v.resetView(); });
    var full = this.fig.querySelector(".replay-full");
    if (!this.fig.requestFullscreen) full.hidden = true;
    full.addEventListener("click", function () {
      if (document.fullscreenElement) document.exitFullscreen();
      else v.fig.requestFullscreen().catch(function () {});
    });
    this.stage.addEventListener("keydown", function (e) {
      var step = e.shiftKey ? 0.1 : 1;
      if (e.key === " " || e.key === "k") v.toggle();
      else if (e.key === "ArrowRight") { v.setPlaying(false); v.seek(v.t + step); v.draw(); }
      else if (e.key === "ArrowLeft") { v.setPlaying(false); v.seek(v.t - step); v.draw(); }
      else if (e.key === "Home") { v.seek(0); v.draw(); }
      else if (e.key === "End") { v.seek(v.duration); v.draw(); }
      else return;
      e.preventDefault();
    });
  };

  Viewer.prototype.toggle = function () {
    if (!this.started) this.start(true); // plays once loaded
    else this.setPlaying(!this.playing);
  };

  Viewer.prototype.show = function () {
    var min = Math.floor(this.t * 10) / 10;
    this.slider.value = String(this.t);
    this.clock.textContent = min.toFixed(1) + " / " + this.duration.toFixed(1) + " " + this.unit;
    this.play.textContent = this.playing ? "❚❚" : "▶";
    this.play.setAttribute("aria-label", this.playing ? this.play.dataset.pause : this.play.dataset.play);
    this.play.setAttribute("aria-pressed", this.playing ? "true" : "false");
    if (this.cursor && this.plot) {
      var x0 = parseFloat(this.plot.dataset.x0), x1 = parseFloat(this.plot.dataset.x1);
      var end = parseFloat(this.plot.dataset.tEnd) || this.duration || 1;
      var x = x0 + Math.min(1, Math.max(0, this.t / end)) * (x1 - x0);
      this.cursor.setAttribute("x1", x.toFixed(1));
      this.cursor.setAttribute("x2", x.toFixed(1));
    }
  };

  Viewer.prototype.start = function (wantPlay) {
    if (this.started) return this.ready;
    this.started = true;
    var v = this, fig = this.fig;
    if (!hasWebGL()) {
      fig.dataset.state = "no-webgl";
      fig.querySelector(".replay-note").hidden = false;
      this.bar.hidden = true;
      return Promise.resolve();
    }
    fig.dataset.state = "loading";
    mark("sitegen-replay-start");
    this.ready = Promise.all([
      loadThree(fig.dataset.three).then(function (T) { mark("sitegen-replay-three"); return T; }),
      loadData(fig.dataset.replay, fig.dataset.glb).then(function (d) { mark("sitegen-replay-data"); return d; })
    ])
      .then(function (got) {
        var buffer = typeof got[1] === "string" ? decode(got[1]) : got[1];
        mark("sitegen-replay-decoded");
        return v.build(got[0], buffer);
      })
      .then(function () {
        fig.dataset.state = "ready";
        if (wantPlay === undefined ? !reduced : wantPlay) v.setPlaying(true);
      })
      .catch(function (err) {
        fig.dataset.state = "failed";
        var note = fig.querySelector(".replay-note");
        note.textContent = fig.dataset.failed || note.textContent;
        note.hidden = false;
        console.error("replay " + fig.id + ": " + err.message);
      });
    return this.ready;
  };

  Viewer.prototype.build = function (T, buffer) {
    var v = this;
    this.T = T;
    return new Promise(function (resolve, reject) {
      new T.GLTFLoader().parse(buffer, "", function (gltf) {
        mark("sitegen-replay-parsed");
        try { v.setup(T, gltf); resolve(); } catch (e) { reject(e); }
      }, function (e) { reject(e instanceof Error ? e : new Error(String(e && e.message || e))); });
    });
  };

  Viewer.prototype.setup = function (T, gltf) {
    var v = this;
    var scene = (this.scene = new T.Scene()); // a glTF scene is a Group: no background
    scene.add(gltf.scene);
    this.root = scene.getObjectByName("replay");
    scene.updateMatrixWorld(true);
    scene.traverse(function (o) { // Lambert: a far smaller shader than glTF's PBR one (first frame)
      if (o.isMesh && o.material && o.material.isMeshStandardMaterial) {
        var m = o.material;
        o.material = new T.MeshLambertMaterial({ color: m.color, side: m.side, name: m.name });
        m.dispose();
      }
    });
    var ratio = Math.min(window.devicePixelRatio || 1, 2);
    // dense screens need no multisampling, and a software GPU draws 4x the pixels at 2x
    var renderer = (this.renderer = new T.WebGLRenderer({ antialias: ratio < 1.5 }));
    mark("sitegen-replay-renderer");
    renderer.setPixelRatio(ratio);
    var canvas = renderer.domElement;
    canvas.className = "replay-canvas";
    canvas.setAttribute("role", "img");
    canvas.setAttribute("aria-label", this.fig.dataset.label || "");
    scene.add(new T.HemisphereLight(0xffffff, 0x5a6270, 1.1));
    var sun = new T.DirectionalLight(0xffffff, 1.3);
    sun.position.set(2, 5, 3);
    scene.add(sun);
    var start = scene.getObjectByName("camera");
    var fov = start && start.isPerspectiveCamera ? start.fov : 50;
    this.camera = new T.PerspectiveCamera(fov, 4 / 3, 0.01, 100);
    this.home = { position: new T.Vector3(), quaternion: new T.Quaternion(), target: new T.Vector3() };
    if (start) {
      start.getWorldPosition(this.home.position);
      start.getWorldQuaternion(this.home.quaternion);
      var tg = (start.userData && start.userData.target) || [0, 0, 0];
      this.home.target.set(tg[0], tg[1], tg[2]);
      this.root.localToWorld(this.home.target);
    }
    this.controls = new T.OrbitControls(this.camera, canvas);
    this.controls.addEventListener("change", function () { v.draw(); });
    this.resetView();
    if (gltf.animations.length) {
      this.mixer = new T.AnimationMixer(scene);
      this.action = this.mixer.clipAction(gltf.animations[0]);
      this.action.setLoop(T.LoopOnce, 1);
      this.action.clampWhenFinished = true;
      this.action.play();
      this.duration = this.duration || gltf.animations[0].duration;
    }
    var trail = scene.getObjectByName("trail");
    this.trail = trail && trail.geometry && trail.geometry.attributes._time ? trail : null;
    this.paint();
    var img = this.stage.querySelector(".replay-poster");
    this.stage.insertBefore(canvas, img);
    img.hidden = true;
    this.resize();
    if (window.ResizeObserver) new ResizeObserver(function () { v.resize(); }).observe(this.stage);
    var watch = function () { v.paint(); v.draw(); };
    new MutationObserver(watch).observe(document.documentElement, { attributes: true, attributeFilter: ["data-theme"] });
    if (window.matchMedia) matchMedia("(prefers-color-scheme: dark)").addEventListener("change", watch);
    this.seek(this.t);
    this.draw();
  };

  Viewer.prototype.paint = function () {
    var bg = getComputedStyle(this.fig).getPropertyValue("--replay-bg").trim() || "#dde3ea";
    this.scene.background = new this.T.Color(bg);
  };

  Viewer.prototype.resize = function () {
    var w = this.stage.clientWidth || 480;
    var h = this.stage.clientHeight || Math.round(w * 0.75);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.draw();
  };

  Viewer.prototype.resetView = function () {
    if (!this.camera) return;
    this.camera.position.copy(this.home.position);
    this.camera.quaternion.copy(this.home.quaternion);
    this.controls.target.copy(this.home.target);
    this.controls.update();
    this.draw();
  };

  Viewer.prototype.orbit = function (radians) {
    var offset = this.camera.position.clone().sub(this.controls.target);
    offset.applyAxisAngle(new this.T.Vector3(0, 1, 0), radians);
    this.camera.position.copy(this.controls.target).add(offset);
    this.controls.update();
    this.draw();
  };

  Viewer.prototype.seek = function (t) {
    this.t = Math.min(this.duration, Math.max(0, t || 0));
    if (this.action) {
      this.action.enabled = true;
      this.action.paused = false;
      this.action.time = this.t;
      this.mixer.update(0);
    }
    if (this.trail) {
      var times = this.trail.geometry.attributes._time.array, lo = 0, hi = times.length;
      while (lo < hi) { var mid = (lo + hi) >> 1; if (times[mid] <= this.t) lo = mid + 1; else hi = mid; }
      this.trail.geometry.setDrawRange(0, lo);
    }
    this.show();
  };

  Viewer.prototype.setPlaying = function (on) {
    this.autoPaused = false;
    if (on === this.playing || !this.renderer) { this.playing = on && !!this.renderer; this.show(); return; }
    this.playing = on;
    this.show();
    if (!on) return;
    var v = this, last = performance.now();
    if (this.t >= this.duration) this.seek(0);
    var tick = function (now) {
      if (!v.playing) return;
      var t = v.t + ((now - last) / 1000) * v.speed;
      last = now;
      v.seek(t >= v.duration ? (v.t >= v.duration ? 0 : v.duration) : t);
      v.draw();
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  };

  Viewer.prototype.draw = function () {
    if (!this.renderer) return;
    this.renderer.render(this.scene, this.camera);
    if (this.frames++ === 0 && performance.mark) performance.mark("sitegen-replay-first-frame");
  };

  Viewer.prototype.pose = function (name) {
    if (!this.scene) return null;
    var obj = this.scene.getObjectByName(this.T.PropertyBinding.sanitizeNodeName(name));
    if (!obj) return null;
    this.scene.updateMatrixWorld(true);
    var p = obj.getWorldPosition(new this.T.Vector3());
    this.root.worldToLocal(p);
    var q = this.root.getWorldQuaternion(new this.T.Quaternion()).invert();
    q.multiply(obj.getWorldQuaternion(new this.T.Quaternion()));
    return { position: [p.x, p.y, p.z], quaternion: [q.x, q.y, q.z, q.w] };
  };

  Viewer.prototype.showObject = function (name, on) {
    var obj = this.scene && this.scene.getObjectByName(this.T.PropertyBinding.sanitizeNodeName(name));
    if (obj) { obj.visible = !!on; this.draw(); }
  };

  Viewer.prototype.screen = function (name) {
    var obj = this.scene && this.scene.getObjectByName(this.T.PropertyBinding.sanitizeNodeName(name));
    if (!obj) return null;
    var p = obj.getWorldPosition(new this.T.Vector3()).project(this.camera);
    var r = this.renderer.domElement.getBoundingClientRect();
    return [r.left + ((p.x + 1) / 2) * r.width, r.top + ((1 - p.y) / 2) * r.height];
  };

  function init() {
    var figures = document.querySelectorAll("figure.clip-replay");
    var seen = window.IntersectionObserver && new IntersectionObserver(function (entries) {
      entries.forEach(function (e) {
        var v = e.target.sitegenViewer;
        if (e.isIntersecting && !v.started && !reduced) v.start();
        if (!e.isIntersecting && v.playing) { v.setPlaying(false); v.autoPaused = true; }
        else if (e.isIntersecting && v.autoPaused) { v.autoPaused = false; v.setPlaying(true); }
      });
    }, { rootMargin: "200px" });
    var height = window.innerHeight || document.documentElement.clientHeight;
    figures.forEach(function (fig) {
      fig.sitegenViewer = new Viewer(fig);
      var box = fig.getBoundingClientRect();
      // in view now: start at once (an IntersectionObserver reports only after the first paint)
      if (!reduced && box.bottom > -200 && box.top < height + 200) fig.sitegenViewer.start();
      if (seen) seen.observe(fig);
      else if (!reduced) fig.sitegenViewer.start();
    });
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", init);
  else init();
})();
