// towride 3D view (three.js): the model's bodies as boxes with their inertia, rods to
// their hardpoints, wheels with tyres, force elements as struts, a modal body's FE mesh
// deformed by its modal coordinates (magnified), the road with the obstacle and the tyre
// contact points; moved by a run's poses (report.js) or by a mode shape (linear.js).
// Built by report::scene3d; world axes are z up.
"use strict";
function View3D(V, host, opts) {
  const T = THREE;
  const self = { mag: opts.mag || 1, onTime: null };
  const canvas = el("canvas", { id: "view3d", width: opts.width, height: opts.height, style: "border:1px solid #ccc;cursor:grab" });
  host.append(canvas);
  let renderer;
  try {
    renderer = new T.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    host.append(el("p", { class: "failed" }, `3D view: WebGL is not available in this browser (${e.message || e}).`));
    document.body.setAttribute("data-view", "no webgl: " + (e.message || e));
    return null;
  }
  renderer.setClearColor(0xf4f6f8);
  const scene = new T.Scene();
  scene.add(new T.AmbientLight(0xffffff, 0.55));
  const sun = new T.DirectionalLight(0xffffff, 0.9);
  sun.position.set(-3, -5, 8);
  scene.add(sun);
  const camera = new T.PerspectiveCamera(35, opts.width / opts.height, 0.05, 500);
  camera.up.set(0, 0, 1);

  const mat = (c, o) => new T.MeshLambertMaterial(Object.assign({ color: c }, o || {}));
  const cyl = new T.CylinderGeometry(1, 1, 1, 10);
  const Y = new T.Vector3(0, 1, 0);
  // A unit cylinder (axis y) stretched from a to b with radius r.
  const place = (mesh, a, b, r) => {
    const d = new T.Vector3().subVectors(b, a);
    const len = d.length();
    mesh.visible = len > 1e-6;
    if (!mesh.visible) return;
    mesh.position.copy(a).addScaledVector(d, 0.5);
    mesh.quaternion.setFromUnitVectors(Y, d.divideScalar(len));
    mesh.scale.set(r, len, r);
  };
  const v3 = (p) => new T.Vector3(p[0], p[1], p[2]);

  // --- bodies
  const groups = V.bodies.map((b, k) => {
    const g = new T.Group();
    scene.add(g);
    const big = Math.max(...b.box) > 1.0;
    if (!b.wheel && !b.flex) {
      const box = new T.Mesh(new T.BoxGeometry(b.box[0], b.box[1], b.box[2]),
        mat(big ? 0x4a7fb5 : 0x8c8c8c, big ? { transparent: true, opacity: 0.35, depthWrite: false } : {}));
      box.quaternion.set(b.box_q[1], b.box_q[2], b.box_q[3], b.box_q[0]);
      g.add(box);
    }
    // Rods from the centre of mass to the hardpoints something acts on.
    if (!b.flex) {
      V.markers.forEach((m) => {
        if (m.b !== k || !m.used) return;
        const rod = new T.Mesh(cyl, mat(big ? 0x9fb4c8 : 0x555555));
        place(rod, new T.Vector3(), v3(m.p), big ? 0.008 : 0.014);
        g.add(rod);
      });
    }
    return g;
  });
  // Tyres: cylinders of the tyre's radius and width about the wheel marker's y axis, a
  // spoke to show the spin.
  const tyreMeshes = V.tyres.map((t) => {
    const m = V.markers[t.marker];
    const w = new T.Group();
    w.position.copy(v3(m.p));
    w.quaternion.setFromUnitVectors(Y, v3(t.axis).normalize());
    w.add(new T.Mesh(new T.CylinderGeometry(t.radius, t.radius, t.width, 40), mat(0x222222)));
    const spoke = new T.Mesh(new T.BoxGeometry(2 * t.radius * 0.9, t.width * 1.05, 0.06), mat(0xd0d0d0));
    w.add(spoke);
    groups[m.b].add(w);
    return w;
  });
  // Modal bodies: FE mesh as rods, deformed each frame.
  const flex = V.bodies.map((b, k) => {
    if (!b.flex) return null;
    const rods = b.flex.edges.map(() => {
      const r = new T.Mesh(cyl, mat(0xd55e00));
      groups[k].add(r);
      return r;
    });
    return { rods, pts: b.flex.pts.map(v3), shapes: b.flex.shapes };
  });
  // A marker's position in its body's axes, deformed on a modal body.
  const local = (m, eta) => {
    const p = v3(m.p);
    const f = m.b >= 0 && flex[m.b];
    if (f && m.node >= 0) {
      for (let j = 0; j < eta.length; j++) {
        const s = f.shapes[j][m.node];
        p.x += self.mag * eta[j] * s[0]; p.y += self.mag * eta[j] * s[1]; p.z += self.mag * eta[j] * s[2];
      }
    }
    return p;
  };
  const strutColour = { spring: 0x009e73, damper: 0xcc79a7, bushing: 0xe69f00 };
  const struts = V.struts.map((s) => {
    const r = new T.Mesh(cyl, mat(strutColour[s.kind] || 0x0072b2));
    scene.add(r);
    return r;
  });

  // --- road: a height grid, the obstacle in a second colour
  const R = V.road;
  if (R) {
    const nx = R.x.length, ny = R.y.length;
    const pos = new Float32Array(nx * ny * 3), col = new Float32Array(nx * ny * 3);
    const base = R.z[0][0];
    for (let j = 0; j < ny; j++) for (let i = 0; i < nx; i++) {
      const o = 3 * (j * nx + i), z = R.z[j][i];
      pos[o] = R.x[i]; pos[o + 1] = R.y[j]; pos[o + 2] = z;
      const ob = Math.abs(z - base) > 1e-3;
      col[o] = ob ? 0.85 : 0.62; col[o + 1] = ob ? 0.55 : 0.64; col[o + 2] = ob ? 0.2 : 0.66;
    }
    const idx = [];
    for (let j = 0; j + 1 < ny; j++) for (let i = 0; i + 1 < nx; i++) {
      const a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      idx.push(a, b, d, a, d, c);
    }
    const geo = new T.BufferGeometry();
    geo.setAttribute("position", new T.BufferAttribute(pos, 3));
    geo.setAttribute("color", new T.BufferAttribute(col, 3));
    geo.setIndex(idx);
    geo.computeVertexNormals();
    scene.add(new T.Mesh(geo, new T.MeshLambertMaterial({ vertexColors: true, side: T.DoubleSide })));
  }
  // Road height under (x, y): bilinear in the grid.
  const below = (x, y) => {
    if (!R) return -Infinity;
    const find = (a, v) => {
      let lo = 0, hi = a.length - 1;
      if (v <= a[0]) return [0, 0];
      if (v >= a[hi]) return [hi - 1, 1];
      while (hi - lo > 1) { const m = (lo + hi) >> 1; if (a[m] <= v) lo = m; else hi = m; }
      return [lo, (v - a[lo]) / (a[lo + 1] - a[lo])];
    };
    const [i, u] = find(R.x, x), [j, w] = find(R.y, y);
    const z = (jj, ii) => R.z[Math.min(jj, R.y.length - 1)][Math.min(ii, R.x.length - 1)];
    return (1 - w) * ((1 - u) * z(j, i) + u * z(j, i + 1)) + w * ((1 - u) * z(j + 1, i) + u * z(j + 1, i + 1));
  };
  // Contact patches: flat red discs a little wider than the tyre, so they show beside it.
  const contacts = V.tyres.map((t) => {
    const s = new T.Mesh(new T.CylinderGeometry(0.75 * t.width, 0.75 * t.width, 0.012, 24), mat(0xe00000));
    s.rotation.x = Math.PI / 2;
    scene.add(s);
    return s;
  });

  // --- camera: orbit about the vehicle's mass centre (drag), zoom (wheel)
  let az = -1.95, el_ = 0.3, dist = opts.dist || 9;
  let dragging = null;
  canvas.addEventListener("mousedown", (e) => { dragging = [e.clientX, e.clientY]; });
  window.addEventListener("mouseup", () => { dragging = null; });
  window.addEventListener("mousemove", (e) => {
    if (!dragging) return;
    az -= (e.clientX - dragging[0]) * 0.008;
    el_ = Math.max(-0.2, Math.min(1.5, el_ + (e.clientY - dragging[1]) * 0.008));
    dragging = [e.clientX, e.clientY];
    self.draw();
  });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    dist = Math.max(1, Math.min(80, dist * (e.deltaY > 0 ? 1.1 : 0.9)));
    self.draw();
  }, { passive: false });
  const totalMass = V.bodies.reduce((a, b) => a + b.mass, 0);

  // pose(b) -> { r: [3], p: [w, x, y, z], eta: [] }, set by the caller.
  self.pose = null;
  self.draw = () => {
    if (!self.pose) return;
    const centre = new T.Vector3();
    const etas = [];
    V.bodies.forEach((b, k) => {
      const P = self.pose(k);
      groups[k].position.set(P.r[0], P.r[1], P.r[2]);
      groups[k].quaternion.set(P.p[1], P.p[2], P.p[3], P.p[0]).normalize();
      groups[k].updateMatrixWorld(true);
      centre.addScaledVector(groups[k].position, b.mass / totalMass);
      etas.push(P.eta);
      const f = flex[k];
      if (f) {
        const pts = f.pts.map((p0, n) => {
          const p = p0.clone();
          P.eta.forEach((e, j) => {
            const s = f.shapes[j][n];
            p.x += self.mag * e * s[0]; p.y += self.mag * e * s[1]; p.z += self.mag * e * s[2];
          });
          return p;
        });
        b.flex.edges.forEach((ed, i) => place(f.rods[i], pts[ed[0]], pts[ed[1]], 0.015));
      }
    });
    const world = (mi) => {
      const m = V.markers[mi];
      const p = local(m, m.b >= 0 ? etas[m.b] : []);
      return m.b >= 0 ? p.applyMatrix4(groups[m.b].matrixWorld) : p;
    };
    V.struts.forEach((s, i) => place(struts[i], world(s.i), world(s.j), 0.02));
    V.tyres.forEach((t, i) => {
      const c = world(t.marker);
      const h = below(c.x, c.y);
      contacts[i].position.set(c.x, c.y, h + 0.006);
      // In contact while the centre is within the unloaded radius of the road.
      contacts[i].visible = c.z - h < t.radius;
    });
    camera.position.set(centre.x + dist * Math.cos(el_) * Math.cos(az), centre.y + dist * Math.cos(el_) * Math.sin(az), centre.z + dist * Math.sin(el_));
    camera.lookAt(centre);
    renderer.render(scene, camera);
  };
  // Pixels that differ from the background, and a checksum of the image (browser test).
  self.probe = () => {
    const gl = renderer.getContext();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0, sum = 0;
    for (let i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - 0xf4) + Math.abs(px[i + 1] - 0xf6) + Math.abs(px[i + 2] - 0xf8) > 24) n++;
      sum = (sum * 31 + px[i] + 3 * px[i + 1] + 7 * px[i + 2]) % 1000000007;
    }
    return [n, sum];
  };
  self.canvas = canvas;
  document.body.setAttribute("data-view", "ok");
  return self;
}

// Play, pause, speed and a scrub slider over [t0, t1]; `show(t)` draws time t. Returns
// { setTime(t), time(), bar }.
function Player(t0, t1, show, speeds) {
  const bar = el("div", { class: "player" });
  const play = el("button", { id: "view-play" }, "▶ play");
  const speed = el("select", { id: "view-speed" });
  for (const s of speeds) speed.append(el("option", { value: s }, `${s}×`));
  const slider = el("input", { id: "view-time", type: "range", min: 0, max: 1000, value: 0, style: "width:420px" });
  const label = el("span", { class: "time" });
  bar.append(play, " speed ", speed, " ", slider, " ", label);
  let t = t0, playing = false, last = null;
  const P = {
    bar,
    time: () => t,
    setTime: (x, quiet) => {
      t = Math.max(t0, Math.min(t1, x));
      slider.value = String(Math.round(1000 * (t - t0) / (t1 - t0 || 1)));
      label.textContent = `t = ${t.toFixed(3)} s`;
      show(t, quiet);
    },
    pause: () => { playing = false; play.textContent = "▶ play"; },
  };
  speed.value = speeds.includes(0.1) ? "0.1" : String(speeds[0]);
  play.addEventListener("click", () => {
    playing = !playing;
    play.textContent = playing ? "❚❚ pause" : "▶ play";
    last = null;
    if (playing) requestAnimationFrame(step);
  });
  slider.addEventListener("input", () => { P.pause(); P.setTime(t0 + (t1 - t0) * slider.value / 1000); });
  const step = (now) => {
    if (!playing) return;
    if (last != null) {
      let x = t + ((now - last) / 1000) * +speed.value;
      if (x > t1) x = t0;
      P.setTime(x);
    }
    last = now;
    requestAnimationFrame(step);
  };
  return P;
}
