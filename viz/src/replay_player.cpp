// The replay's player: the script inlined in report.html (report_replay.cpp) that draws
// a variant's track (replay_data.cpp) with three.js r111 and its OrbitControls.
#include "report_replay.hpp"

namespace dmbd::viz::detail {

// Written for three.js r111 (Debian's libjs-three), whose API differs from later ones:
// gammaOutput (not outputEncoding), *BufferGeometry classes. Colours arrive in sRGB and
// are lit in linear light, as the frames' renderer does. The poses are interpolated
// between samples (positions linearly, rotations by slerp); forces, markers and text
// lines are the nearest sample's. Overlays are drawn over the robot (no depth test), as
// the frames draw theirs after the 3-D pass.
const char* const kReplayPlayerJs = R"js(
(function () {
  'use strict';
  const $ = (id) => document.getElementById(id);
  const section = $('replay');
  const setup = JSON.parse($('replay-setup').textContent);
  const params = new URLSearchParams(window.location.search);
  const state = (s) => section.setAttribute('data-state', s);
  function fail(text) {
    $('replay-message').textContent = 'The replay cannot be shown: ' + text;
    state('error');
    console.error('dmbd replay: ' + text);
  }
  if (!window.THREE || !THREE.OrbitControls) {
    fail('three.js did not load (' + setup.scripts.join(', ') + ')');
    return;
  }
  const only = params.get('view') === 'replay';
  if (only) document.body.classList.add('replay-only');

  // ---- decoding (little-endian float32 and integers in base64; every browser's platform is little-endian)
  function buffer(b64) {
    const s = atob(b64), a = new Uint8Array(s.length);
    for (let i = 0; i < s.length; ++i) a[i] = s.charCodeAt(i);
    return a.buffer;
  }
  const floats = (b64) => new Float32Array(buffer(b64));
  const linear = (rgb) => new THREE.Color(rgb[0], rgb[1], rgb[2]).convertSRGBToLinear();
  const rgb255 = (c) => [c[0] / 255, c[1] / 255, c[2] / 255];

  // ---- renderer, camera, lights, ground
  const cam = setup.camera;
  const canvas = $('replay-canvas');
  const renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, alpha: true, preserveDrawingBuffer: true});
  renderer.setClearColor(0x000000, 0);
  renderer.gammaOutput = true;
  renderer.gammaFactor = 2.2;
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = THREE.PCFSoftShadowMap;
  const scene = new THREE.Scene();
  const camera = new THREE.PerspectiveCamera(cam.fov_y_deg, cam.width / cam.height, cam.near_m, 500);
  camera.up.fromArray(cam.up);  // before the controls: they orbit about it
  scene.add(camera);
  const controls = new THREE.OrbitControls(camera, canvas);
  controls.enableDamping = false;
  function resetView() {
    camera.position.fromArray(cam.position);
    controls.target.fromArray(cam.look_at);
    controls.update();
  }
  resetView();

  scene.add(new THREE.HemisphereLight(0xffffff, 0x8c8c8c, 0.45));
  const key = new THREE.DirectionalLight(0xffffff, 0.85);
  key.castShadow = true;
  key.shadow.mapSize.set(2048, 2048);
  key.shadow.bias = -0.0005;
  scene.add(key, key.target);
  const head = new THREE.DirectionalLight(0xffffff, 0.25);  // a fill light from the camera
  scene.add(head, head.target);
  const light_from = new THREE.Vector3().fromArray(setup.light_from).normalize();

  const ground = new THREE.Group();
  const horizon = linear(rgb255([214, 222, 230]));
  scene.fog = new THREE.Fog(horizon, 6, 25);
  const plane = new THREE.Mesh(new THREE.PlaneBufferGeometry(400, 400),
                               new THREE.MeshLambertMaterial({color: linear(rgb255([196, 196, 190]))}));
  plane.receiveShadow = true;
  ground.add(plane);
  // Lines of the ground in pieces of at most 1 m: a long line that passes behind the camera
  // is dropped whole by some WebGL implementations (SwiftShader) instead of clipped.
  const reach = 12, cx = Math.round(cam.look_at[0]), cy = Math.round(cam.look_at[1]);
  function lines(segments, rgb, z) {
    const points = [];
    for (const [x0, y0, x1, y1] of segments) {
      const n = Math.max(1, Math.ceil(Math.hypot(x1 - x0, y1 - y0)));
      for (let k = 0; k < n; ++k)
        points.push(new THREE.Vector3(x0 + (x1 - x0) * k / n, y0 + (y1 - y0) * k / n, z),
                    new THREE.Vector3(x0 + (x1 - x0) * (k + 1) / n, y0 + (y1 - y0) * (k + 1) / n, z));
    }
    ground.add(new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(points),
                                      new THREE.LineBasicMaterial({color: linear(rgb255(rgb))})));
  }
  function grid(step, rgb, z) {
    const segments = [], n = Math.round(reach / step);
    for (let k = -n; k <= n; ++k) {
      if (Math.abs(k * step - Math.round(k * step)) < 1e-9 && step < 1) continue;  // under a major line
      segments.push([cx - reach, cy + k * step, cx + reach, cy + k * step], [cx + k * step, cy - reach, cx + k * step, cy + reach]);
    }
    lines(segments, rgb, z);
  }
  grid(0.1, [160, 160, 156], 0.0005);
  grid(1, [110, 110, 108], 0.001);
  lines([[cx - reach, 0, cx + reach, 0]], [200, 70, 60], 0.0015);  // the world's x axis
  lines([[0, cy - reach, 0, cy + reach]], [70, 160, 70], 0.0015);  // and y axis
  scene.add(ground);

  // ---- the robot: one group per scene body, its meshes made once per scene
  const scenes = {};  // by script path
  function body_groups(data) {
    const materials = {};
    function material(rgba) {
      const k = rgba.join(',');
      if (!materials[k])
        materials[k] = new THREE.MeshPhongMaterial({color: linear(rgba), specular: 0x333333, shininess: 32,
                                                     side: THREE.DoubleSide, fog: false});
      return materials[k];
    }
    return data.bodies.map(function (b) {
      const group = new THREE.Group();
      group.name = b.name;
      for (const m of b.meshes) {
        if (m.rgba[3] <= 0) continue;
        let geometry = new THREE.BufferGeometry();
        geometry.setAttribute('position', new THREE.BufferAttribute(floats(m.positions), 3));
        const index = m.index_bytes === 2 ? new Uint16Array(buffer(m.indices)) : new Uint32Array(buffer(m.indices));
        geometry.setIndex(new THREE.BufferAttribute(index, 1));
        const normals = floats(m.normals);
        if (normals.length > 0) {
          geometry.setAttribute('normal', new THREE.BufferAttribute(normals, 3));
        } else {
          geometry = geometry.toNonIndexed();  // flat faces, as the frames shade a mesh without normals
          geometry.computeVertexNormals();
        }
        const mesh = new THREE.Mesh(geometry, material(m.rgba));
        mesh.castShadow = true;
        group.add(mesh);
      }
      return group;
    });
  }

  // ---- overlays
  const overlays = new THREE.Group();
  overlays.renderOrder = 10;
  scene.add(overlays);
  function on_top(object) {
    object.traverse(function (o) {
      o.renderOrder = 10;
      if (o.material) {
        o.material.depthTest = false;
        o.material.transparent = true;  // drawn after the opaque robot
        o.material.fog = false;
      }
    });
    overlays.add(object);
    return object;
  }
  const force_colour = linear(rgb255([230, 50, 40])), com_colour = linear(rgb255([255, 210, 0]));
  function ring(radius, colour) {
    const points = [];
    for (let k = 0; k <= 48; ++k)
      points.push(new THREE.Vector3(radius * Math.cos(k * Math.PI / 24), radius * Math.sin(k * Math.PI / 24), 0));
    return new THREE.Line(new THREE.BufferGeometry().setFromPoints(points), new THREE.LineBasicMaterial({color: colour}));
  }
  function cross(half, colour) {
    const v = (x, y) => new THREE.Vector3(x, y, 0);
    return new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints([v(-half, 0), v(half, 0), v(0, -half), v(0, half)]),
                                  new THREE.LineBasicMaterial({color: colour}));
  }
  const com = {
    ball: on_top(new THREE.Mesh(new THREE.SphereBufferGeometry(0.02, 16, 8), new THREE.MeshBasicMaterial({color: com_colour}))),
    ring: on_top(ring(0.05, com_colour)),
    drop: on_top(new THREE.Line(new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3()]),
                                new THREE.LineDashedMaterial({color: com_colour, dashSize: 0.03, gapSize: 0.02}))),
  };

  // ---- the track shown
  let track = null, groups = null, current = null;
  let time = 0, playing = false, speed = 1, last_frame = null;
  const slider = $('replay-time'), clock = $('replay-clock'), play = $('replay-play'), hud = $('replay-hud');

  function decode(t, bodies) {
    const out = {name: t.name, samples: t.samples, bodies: t.bodies, times: floats(t.times), poses: floats(t.poses),
                 com: floats(t.com), sites: t.sites, forces: floats(t.forces), paths: [], markers: [], texts: []};
    if (out.bodies !== bodies) throw new Error('the track has ' + out.bodies + ' bodies, its scene ' + bodies);
    for (const p of t.paths) {
      const material = p.dashed ? new THREE.LineDashedMaterial({color: linear(rgb255(p.rgb)), dashSize: 0.03, gapSize: 0.02})
                                : new THREE.LineBasicMaterial({color: linear(rgb255(p.rgb))});
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(3 * (t.samples + 1)), 3));
      out.paths.push({label: p.label, rgb: p.rgb, window_s: p.window_s, dashed: p.dashed, points: floats(p.points),
                      line: new THREE.Line(geometry, material)});
    }
    for (const m of t.markers) {
      const marker = new THREE.Group();
      marker.add(ring(m.ring_m, linear(rgb255(m.rgb))), cross(0.5 * m.ring_m, linear(rgb255(m.rgb))));
      out.markers.push({label: m.label, rgb: m.rgb, points: floats(m.points), object: marker});
    }
    for (const x of t.texts) out.texts.push({label: x.label, names: x.names, values: floats(x.values)});
    out.arrows = [];
    for (let s = 0; s < t.sites; ++s)
      out.arrows.push(new THREE.ArrowHelper(new THREE.Vector3(0, 0, 1), new THREE.Vector3(), 1, force_colour, 0.05, 0.03));
    out.radius = 1;  // the robot's reach from the view's centre over the run: the shadow's extent
    const centre = new THREE.Vector3().fromArray(cam.look_at), p = new THREE.Vector3();
    for (let k = 0; k < out.poses.length; k += 7)
      out.radius = Math.max(out.radius, p.set(out.poses[k], out.poses[k + 1], out.poses[k + 2]).distanceTo(centre) + 1);
    return out;
  }

  // The sample at or before t and the fraction of the way to the next.
  function locate(t) {
    const times = track.times;
    let lo = 0, hi = times.length - 1;
    if (t <= times[0]) return [0, 0];
    if (t >= times[hi]) return [hi, 0];
    while (hi - lo > 1) {
      const mid = (lo + hi) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid;
    }
    return [lo, (t - times[lo]) / (times[lo + 1] - times[lo])];
  }
  const finite = (a, k) => isFinite(a[k]) && isFinite(a[k + 1]) && isFinite(a[k + 2]);
  function point(a, i, j, f, out) {
    const k = 3 * i, l = 3 * j;
    if (!finite(a, k)) return null;
    if (!finite(a, l) || f === 0) return out.set(a[k], a[k + 1], a[k + 2]);
    return out.set(a[k] + f * (a[l] - a[k]), a[k + 1] + f * (a[l + 1] - a[k + 1]), a[k + 2] + f * (a[l + 2] - a[k + 2]));
  }
  function format(v) {
    if (!isFinite(v)) return String(v);
    return Math.abs(v - Math.round(v)) < 1e-9 ? String(Math.round(v)) : Number(v.toPrecision(4)).toString();
  }
  const escape = (s) => String(s).replace(/[&<>"']/g, (c) => '&#' + c.charCodeAt(0) + ';');

  const qa = new THREE.Quaternion(), qb = new THREE.Quaternion(), v = new THREE.Vector3(), w = new THREE.Vector3();
  function show() {
    if (!track) return;
    const [i, f] = locate(time), j = Math.min(i + 1, track.samples - 1), near = f < 0.5 ? i : j;
    const P = track.poses, n = track.bodies;
    for (let b = 0; b < n; ++b) {
      const a = 7 * (i * n + b), c = 7 * (j * n + b), g = groups[b];
      g.position.set(P[a] + f * (P[c] - P[a]), P[a + 1] + f * (P[c + 1] - P[a + 1]), P[a + 2] + f * (P[c + 2] - P[a + 2]));
      qa.set(P[a + 3], P[a + 4], P[a + 5], P[a + 6]);
      qb.set(P[c + 3], P[c + 4], P[c + 5], P[c + 6]);
      g.quaternion.copy(qa).slerp(qb, f);
    }
    const show_overlays = $('replay-overlays').checked;
    overlays.visible = show_overlays;
    hud.hidden = !show_overlays;
    const c = track.com.length ? point(track.com, i, j, f, v) : null;
    for (const o of [com.ball, com.ring, com.drop]) o.visible = c !== null;
    if (c) {
      com.ball.position.copy(c);
      com.ring.position.set(c.x, c.y, 0.002);
      com.drop.geometry.attributes.position.array.set([c.x, c.y, c.z, c.x, c.y, 0]);
      com.drop.geometry.attributes.position.needsUpdate = true;
      com.drop.geometry.computeBoundingSphere();
      com.drop.computeLineDistances();
    }
    const F = track.forces;
    track.arrows.forEach(function (arrow, s) {
      const k = 6 * (near * track.sites + s);
      w.set(F[k + 3], F[k + 4], F[k + 5]);
      const length = w.length() * setup.force_scale_m_per_N;
      arrow.visible = isFinite(length) && w.length() > 1e-3;
      if (!arrow.visible) return;
      arrow.position.set(F[k], F[k + 1], F[k + 2]);
      arrow.setDirection(w.normalize());
      arrow.setLength(length, Math.min(0.05, 0.4 * length), Math.min(0.03, 0.25 * length));
    });
    for (const p of track.paths) {
      const array = p.line.geometry.attributes.position.array;
      let count = 0;
      for (let k = locate(time - p.window_s)[0]; k <= i; ++k)
        if (finite(p.points, 3 * k)) array.set(p.points.subarray(3 * k, 3 * k + 3), 3 * count++);
      if (f > 0 && point(p.points, i, j, f, v)) array.set([v.x, v.y, v.z], 3 * count++);
      p.line.geometry.setDrawRange(0, count);
      p.line.geometry.attributes.position.needsUpdate = true;
      p.line.geometry.computeBoundingSphere();
      if (p.dashed) p.line.computeLineDistances();
    }
    for (const m of track.markers) {
      const at = point(m.points, near, near, 0, v);
      m.object.visible = at !== null;
      if (at) m.object.position.copy(at);
    }
    let lines = [escape(setup.title + '  |  ' + track.name), 't = ' + time.toFixed(3) + ' s'];
    for (const x of track.texts) {
      const value = x.values[near], k = Math.round(value);
      const named = isFinite(value) && k >= 0 && k < x.names.length && Math.abs(value - k) < 1e-6;
      lines.push(escape(x.label + ': ' + (named ? x.names[k] : format(value))));
    }
    let legend = '';
    for (const o of track.paths.concat(track.markers))
      if (o.label)
        legend += '<div><span class="swatch' + (o.dashed ? ' dashed' : '') + '" style="border-color:rgb(' + o.rgb.join(',') +
                  ')"></span>' + escape(o.label) + '</div>';
    hud.innerHTML = '<div class="lines">' + lines.join('<br>') + '</div>' + (legend ? '<div class="legend">' + legend + '</div>' : '');
    slider.value = time;
    clock.textContent = 't = ' + time.toFixed(3) + ' s';
    render();
    section.setAttribute('data-time', time.toFixed(6));
  }

  function render() {
    const show_ground = $('replay-ground').checked;
    ground.visible = show_ground;
    scene.fog = show_ground ? scene.fog || new THREE.Fog(horizon, 6, 25) : null;
    key.castShadow = show_ground;
    const target = controls.target;
    if (track) {
      key.position.copy(target).addScaledVector(light_from, 2 * track.radius + 5);
      key.target.position.copy(target);
      const s = key.shadow.camera;
      s.left = s.bottom = -track.radius;
      s.right = s.top = track.radius;
      s.near = 0.1;
      s.far = 4 * track.radius + 10;
      s.updateProjectionMatrix();
    }
    head.position.copy(camera.position);
    head.target.position.copy(target);
    renderer.render(scene, camera);
  }

  function resize() {
    const width = only ? cam.width : canvas.parentElement.clientWidth;
    const height = only ? cam.height : Math.round(width * cam.height / cam.width);
    renderer.setPixelRatio(only ? 1 : window.devicePixelRatio || 1);
    renderer.setSize(width, height, false);
    canvas.style.width = width + 'px';
    canvas.style.height = height + 'px';
    render();
  }

  // ---- loading a variant: its scene's and its track's scripts, each once
  const loaded = {};
  function load(path) {
    if (!loaded[path])
      loaded[path] = new Promise(function (resolve, reject) {
        const s = document.createElement('script');
        s.src = path;
        s.async = false;
        s.onload = resolve;
        s.onerror = () => reject(new Error('cannot load ' + path));
        document.head.appendChild(s);
      });
    return loaded[path];
  }
  const select = $('replay-variant');
  function choose(index, at) {
    const option = select.options[index];
    select.selectedIndex = index;
    state('loading');
    Promise.all([load(option.dataset.scene), load(option.dataset.track)]).then(function () {
      const store = window.dmbdReplay;
      const scene_data = store && store.scenes[option.dataset.scene], track_data = store && store.tracks[option.dataset.track];
      if (!scene_data || !track_data) throw new Error(option.dataset.track + ' or ' + option.dataset.scene + ' holds no replay data');
      if (!scenes[option.dataset.scene]) scenes[option.dataset.scene] = body_groups(scene_data);
      const next = decode(track_data, scenes[option.dataset.scene].length);
      if (track) {
        for (const g of groups) scene.remove(g);
        for (const o of track.paths) overlays.remove(o.line);
        for (const o of track.markers) overlays.remove(o.object);
        for (const a of track.arrows) overlays.remove(a);
      }
      track = next;
      groups = scenes[option.dataset.scene];
      for (const g of groups) scene.add(g);
      for (const o of track.paths) on_top(o.line);
      for (const o of track.markers) on_top(o.object);
      for (const a of track.arrows) on_top(a);
      slider.min = track.times[0];
      slider.max = track.times[track.samples - 1];
      time = Math.min(Math.max(at, track.times[0]), track.times[track.samples - 1]);
      show();
      state('ready');
    }).catch((e) => fail(e.message));
  }

  // ---- controls
  function set_playing(p) {
    playing = p && track !== null;
    play.textContent = playing ? 'Pause' : 'Play';
    last_frame = null;
    if (playing) window.requestAnimationFrame(tick);
  }
  function tick(now) {
    if (!playing) return;
    if (last_frame !== null) time += speed * (now - last_frame) / 1000;
    last_frame = now;
    const end = track.times[track.samples - 1];
    if (time >= end) {
      time = end;
      show();
      set_playing(false);
      return;
    }
    show();
    window.requestAnimationFrame(tick);
  }
  play.addEventListener('click', function () {
    if (!playing && track && time >= track.times[track.samples - 1]) time = track.times[0];
    set_playing(!playing);
  });
  slider.addEventListener('input', function () {
    time = parseFloat(slider.value);
    show();
  });
  $('replay-speed').addEventListener('change', (e) => { speed = parseFloat(e.target.value); });
  select.addEventListener('change', () => choose(select.selectedIndex, time));
  $('replay-ground').addEventListener('change', render);
  $('replay-overlays').addEventListener('change', show);
  $('replay-reset').addEventListener('click', function () {
    resetView();
    render();
  });
  controls.addEventListener('change', render);
  window.addEventListener('resize', resize);

  // ---- URL parameters, then the first variant
  if (params.get('ground') === '0') $('replay-ground').checked = false;
  if (params.get('overlays') === '0') $('replay-overlays').checked = false;
  if (params.has('speed') && parseFloat(params.get('speed')) > 0) {
    speed = parseFloat(params.get('speed'));
    $('replay-speed').value = String(speed);
  }
  let first = setup.initial;
  if (params.has('variant')) {
    const wanted = params.get('variant');
    const k = Array.prototype.findIndex.call(select.options, (o) => o.textContent === wanted);
    if (k < 0) {
      fail('no variant \'' + wanted + '\' in this replay');
      return;
    }
    first = k;
  }
  resize();
  choose(first, params.has('t') ? parseFloat(params.get('t')) || 0 : -Infinity);
})();
)js";

}  // namespace dmbd::viz::detail
