// The page of a hamel scene: the model's bodies at each sample of a trajectory, drawn with
// three.js (embedded in the page, so that it opens from disk with no network).
//
// The URL's fragment sets the start: `#t=1.5&pause&speed=0.5&follow=0` (and `hide=2` leaves
// out the third body, for the browser test to see what it covered). The page publishes
// what a test needs to check the picture against the trajectory: `window.hamelScene`
// (`ready`, a promise resolved once the requested time is on screen; `state()`; `setTime`,
// `play`, `pause`; `measure(frames)`, the frame times while playing) and the camera's
// matrices in the `data-` attributes of `<output id="camera">`.
'use strict';

(function () {
  let resolveReady;
  let rejectReady;
  const ready = new Promise((resolve, reject) => {
    resolveReady = resolve;
    rejectReady = reject;
  });
  ready.catch(() => {});
  window.hamelScene = { ready };

  function fail(error) {
    const box = document.getElementById('error');
    box.hidden = false;
    box.textContent = 'The scene cannot be shown: ' + ((error && error.message) || error);
    console.error(error);
    rejectReady(error);
  }

  // three.js, from the text of the page's script elements: its two module files import
  // each other by relative name, which a blob: URL cannot resolve, so the import names are
  // replaced by the blob URLs themselves.
  async function loadThree() {
    const text = (id) => document.getElementById(id).textContent;
    const url = (source) => URL.createObjectURL(new Blob([source], { type: 'text/javascript' }));
    const replaced = (source, from, to) => {
      const parts = source.split(from);
      if (parts.length < 2) {
        throw new Error('the embedded three.js no longer imports ' + from);
      }
      return parts.join(to);
    };
    const core = url(text('three-core'));
    const module = url(replaced(text('three-module'), '"./three.core.min.js"', JSON.stringify(core)));
    const orbit = url(replaced(text('three-orbit'), "from 'three'", 'from ' + JSON.stringify(module)));
    const THREE = await import(module);
    const { OrbitControls } = await import(orbit);
    return { THREE, OrbitControls };
  }

  function decode(base64, Type) {
    const binary = atob(base64);
    const bytes = new Uint8Array(binary.length);
    for (let i = 0; i < binary.length; i++) bytes[i] = binary.charCodeAt(i);
    return new Type(bytes.buffer);
  }

  function fragment() {
    const options = { t: null, pause: false, speed: null, follow: null, hide: [] };
    for (const part of window.location.hash.replace(/^#/, '').split('&')) {
      const [key, value] = part.split('=');
      if (key === 't' && value !== undefined && isFinite(Number(value))) options.t = Number(value);
      if (key === 'pause') options.pause = true;
      if (key === 'speed' && Number(value) > 0) options.speed = Number(value);
      if (key === 'follow') options.follow = value !== '0';
      if (key === 'hide' && /^[0-9]+$/.test(value || '')) options.hide.push(Number(value));
    }
    return options;
  }

  // A number in four significant digits, without an exponent where it can do without.
  function short(x) {
    if (!isFinite(x)) return String(x);
    if (x === 0) return '0';
    const magnitude = Math.floor(Math.log10(Math.abs(x)));
    if (magnitude < -3 || magnitude > 4) return x.toExponential(3);
    return x.toFixed(Math.max(0, 3 - magnitude));
  }
  // The same without trailing zeros, for prose.
  const brief = (x) => (short(x).includes('.') && !short(x).includes('e') ? short(x).replace(/\.?0+$/, '') : short(x));

  const css = (color) => '#' + color.toString(16).padStart(6, '0');

  // The meshes of one body's solid, in the body's axes.
  function solidOf(THREE, body) {
    const solid = body.solid;
    const group = new THREE.Group();
    const lit = new THREE.MeshLambertMaterial({ color: body.color });
    const axisTo = (object, from, to) =>
      object.quaternion.setFromUnitVectors(from, new THREE.Vector3(...to).normalize());
    if (solid.kind === 'disk') {
      // Sectors of two colours round a dark hub, so that the spin shows; a tyre at the rim.
      const r = solid.radius;
      const hub = 0.15 * r;
      const disk = new THREE.Group();
      const colors = [body.color, new THREE.Color(body.color).multiplyScalar(0.55)];
      const materials = colors.map((color) => new THREE.MeshBasicMaterial({ color, side: THREE.DoubleSide }));
      const sectors = 8;
      for (let k = 0; k < sectors; k++) {
        const sector = new THREE.RingGeometry(hub, r, 6, 1, (2 * Math.PI * k) / sectors, (2 * Math.PI) / sectors);
        disk.add(new THREE.Mesh(sector, materials[k % 2]));
      }
      const hubMaterial = new THREE.MeshBasicMaterial({ color: HUB, side: THREE.DoubleSide });
      disk.add(new THREE.Mesh(new THREE.CircleGeometry(hub, 24), hubMaterial));
      const tyre = new THREE.Mesh(new THREE.TorusGeometry(r, 0.035 * r, 8, 64), new THREE.MeshLambertMaterial({ color: 0x444444 }));
      disk.add(tyre);
      // Circles and tori lie in the xy plane: turn their normal, z, onto the axle.
      axisTo(disk, new THREE.Vector3(0, 0, 1), solid.axis);
      group.add(disk);
    } else if (solid.kind === 'sphere' || solid.kind === 'marker') {
      const r = solid.radius;
      if (solid.kind === 'marker') {
        group.add(new THREE.Mesh(new THREE.SphereGeometry(r, 16, 12), lit));
      } else {
        // Lunes of two colours, so that the rotation shows.
        const dark = new THREE.MeshLambertMaterial({ color: new THREE.Color(body.color).multiplyScalar(0.55) });
        const lunes = 8;
        for (let k = 0; k < lunes; k++) {
          const lune = new THREE.SphereGeometry(r, 6, 24, (2 * Math.PI * k) / lunes, (2 * Math.PI) / lunes);
          group.add(new THREE.Mesh(lune, k % 2 ? dark : lit));
        }
      }
    } else if (solid.kind === 'ellipsoid' || solid.kind === 'box') {
      const inner = new THREE.Group();
      if (solid.kind === 'ellipsoid') {
        const mesh = new THREE.Mesh(new THREE.SphereGeometry(1, 32, 20), lit);
        mesh.scale.set(...solid.semi_axes);
        inner.add(mesh);
      } else {
        const geometry = new THREE.BoxGeometry(...solid.edges);
        inner.add(new THREE.Mesh(geometry, lit));
        inner.add(new THREE.LineSegments(new THREE.EdgesGeometry(geometry), new THREE.LineBasicMaterial({ color: 0x333333 })));
      }
      inner.quaternion.set(...solid.rotation);
      group.add(inner);
    } else if (solid.kind === 'cylinder') {
      const mesh = new THREE.Mesh(new THREE.CylinderGeometry(solid.radius, solid.radius, solid.length, 32), lit);
      // Cylinders lie along y.
      axisTo(mesh, new THREE.Vector3(0, 1, 0), solid.axis);
      group.add(mesh);
    } else {
      throw new Error('unknown solid ' + solid.kind);
    }
    group.position.set(...body.offset);
    return group;
  }

  // The colour of a wheel's hub (the browser test looks for it at the wheel's centre).
  const HUB = 0x1a1a1a;
  // The triads' colours, as in the pictures: x red, y green, z blue.
  const TRIAD = [0xd62728, 0x2ca02c, 0x1f77b4];

  async function start() {
    const data = JSON.parse(document.getElementById('hamel-data').textContent);
    const { THREE, OrbitControls } = await loadThree();
    document.getElementById('three-version').textContent = 'r' + THREE.REVISION;
    const times = decode(data.times, Float64Array);
    const poses = decode(data.poses, Float32Array);
    const points = decode(data.points, Float32Array);
    const values = decode(data.values, Float64Array);
    const n = times.length;
    const bodies = data.bodies.length;
    const contacts = data.contacts.length;
    const columns = data.columns.length;
    const vector = (a) => new THREE.Vector3(a[0], a[1], a[2]);
    const up = vector(data.up);
    const forward = vector(data.forward);
    const left = vector(data.left);

    const view = document.getElementById('view');
    // No multisampling: in software rendering (SwiftShader, a machine without a GPU) it
    // costs a frame of 16.7 ms or more, for smoother edges only (tests/browser/README.md).
    const renderer = new THREE.WebGLRenderer({ antialias: false });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    view.appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xf4f4f4);
    const reach = data.radius;
    const camera = new THREE.PerspectiveCamera(35, 1, reach / 100, reach * 1000 + data.grid.size * 4);
    camera.up.copy(up);

    const sky = new THREE.HemisphereLight(0xffffff, 0x999999, 2.2);
    sky.position.copy(up);
    scene.add(sky);
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.copy(up.clone().multiplyScalar(3).sub(left).add(forward));
    scene.add(sun);

    // The ground, z = 0: three.js draws its grid in the xz plane.
    const divisions = Math.round(data.grid.size / data.grid.step);
    const grid = new THREE.GridHelper(data.grid.size, divisions, 0xaaaaaa, 0xd4d4d4);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(data.grid.centre[0], data.grid.centre[1], 0);
    scene.add(grid);

    // The bodies, each with its axes as a triad of arrows: x red, y green, z blue.
    const placed = data.bodies.map((body) => {
      const group = new THREE.Group();
      group.add(solidOf(THREE, body));
      const units = [new THREE.Vector3(1, 0, 0), new THREE.Vector3(0, 1, 0), new THREE.Vector3(0, 0, 1)];
      units.forEach((unit, k) => {
        group.add(new THREE.ArrowHelper(unit, new THREE.Vector3(), body.triad, TRIAD[k], 0.12 * body.triad, 0.05 * body.triad));
      });
      scene.add(group);
      return group;
    });

    // Each contact's trace on the ground, drawn up to the shown sample, and a dot where it is.
    const traces = data.contacts.map((contact, j) => {
      const line = new Float32Array(3 * n);
      for (let i = 0; i < n; i++) line.set(points.subarray(3 * (i * contacts + j), 3 * (i * contacts + j) + 3), 3 * i);
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(line, 3));
      const color = contact.body === null ? 0x333333 : new THREE.Color(data.bodies[contact.body].color).multiplyScalar(0.6);
      const trace = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color }));
      scene.add(trace);
      const dot = new THREE.Mesh(new THREE.SphereGeometry(0.02 * reach, 12, 8), new THREE.MeshBasicMaterial({ color: 0x000000 }));
      scene.add(dot);
      return { trace, dot };
    });

    // Gravity's direction, beside the mechanism.
    let arrow = null;
    if (data.gravity) {
      arrow = new THREE.ArrowHelper(vector(data.gravity).normalize(), new THREE.Vector3(), 0.6 * reach, 0x555555, 0.15 * reach, 0.08 * reach);
      scene.add(arrow);
    }

    const centroid = (i) => {
      const c = new THREE.Vector3();
      for (let b = 0; b < bodies; b++) {
        const at = 7 * (i * bodies + b);
        c.x += poses[at];
        c.y += poses[at + 1];
        c.z += poses[at + 2];
      }
      return c.multiplyScalar(1 / bodies);
    };

    // The camera looks at the mechanism's first sample from its right, ahead and above.
    const start = centroid(0);
    const azimuth = (35 * Math.PI) / 180;
    const elevation = (22 * Math.PI) / 180;
    const direction = left.clone().multiplyScalar(-Math.cos(azimuth)).addScaledVector(forward, Math.sin(azimuth)).multiplyScalar(Math.cos(elevation)).addScaledVector(up, Math.sin(elevation));
    camera.position.copy(start).addScaledVector(direction, 6 * reach);
    const controls = new OrbitControls(camera, renderer.domElement);
    controls.target.copy(start);
    controls.update();

    // The panel.
    const panel = {
      time: document.getElementById('time'),
      sample: document.getElementById('sample'),
      values: [],
      output: document.getElementById('camera'),
    };
    const table = document.getElementById('values');
    for (const column of data.columns) {
      const row = table.insertRow();
      row.insertCell().textContent = column.name;
      const value = row.insertCell();
      value.className = 'value';
      row.insertCell().textContent = column.unit || '';
      panel.values.push(value);
    }
    const list = document.getElementById('bodies');
    for (const body of data.bodies) {
      const item = document.createElement('li');
      const swatch = document.createElement('span');
      swatch.className = 'swatch';
      swatch.style.background = css(body.color);
      const note = document.createElement('span');
      note.className = 'note';
      note.textContent = body.description;
      item.append(swatch, body.name, note);
      list.append(item);
    }
    document.getElementById('gravity').textContent = data.gravity
      ? 'Gravity (' + data.gravity.map(brief).join(', ') + ') points along the grey arrow; up is against it.'
      : 'The model has no gravity: up is +z, the ground the plane z = 0.';
    const warnings = document.getElementById('warnings');
    for (const warning of data.warnings) {
      const item = document.createElement('li');
      item.textContent = warning;
      warnings.append(item);
    }
    if (data.warnings.length) console.warn(data.warnings.join('\n'));

    // Playback. `clock` is the playback time; the sample shown is the last one at or before
    // it, so the frames are the samples as computed.
    const options = fragment();
    const controlsBar = {
      play: document.getElementById('play'),
      speed: document.getElementById('speed'),
      slider: document.getElementById('slider'),
      loop: document.getElementById('loop'),
      follow: document.getElementById('follow'),
    };
    controlsBar.slider.max = String(n - 1);
    if (options.speed !== null) {
      const option = document.createElement('option');
      option.value = String(options.speed);
      option.textContent = options.speed + '×';
      controlsBar.speed.append(option);
      controlsBar.speed.value = String(options.speed);
    }
    if (options.follow !== null) controlsBar.follow.checked = options.follow;
    for (const b of options.hide) if (placed[b]) placed[b].visible = false;
    const first = times[0];
    const last = times[n - 1];
    let clock = options.t === null ? first : Math.min(Math.max(options.t, first), last);
    let playing = !options.pause && n > 1;
    let shown = -1;
    let dirty = true;
    let previous = null;

    const sampleAt = (t) => {
      let lo = 0;
      let hi = n - 1;
      if (t >= times[hi]) return hi;
      while (lo < hi) {
        const mid = (lo + hi + 1) >> 1;
        if (times[mid] <= t) lo = mid;
        else hi = mid - 1;
      }
      return lo;
    };

    const follow = (i) => {
      const target = controlsBar.follow.checked ? centroid(i) : start;
      const shift = target.clone().sub(controls.target);
      controls.target.add(shift);
      camera.position.add(shift);
      controls.update();
    };

    const show = (i) => {
      for (let b = 0; b < bodies; b++) {
        const at = 7 * (i * bodies + b);
        placed[b].position.set(poses[at], poses[at + 1], poses[at + 2]);
        placed[b].quaternion.set(poses[at + 3], poses[at + 4], poses[at + 5], poses[at + 6]);
      }
      for (let j = 0; j < contacts; j++) {
        traces[j].trace.geometry.setDrawRange(0, i + 1);
        const at = 3 * (i * contacts + j);
        traces[j].dot.position.set(points[at], points[at + 1], points[at + 2]);
      }
      if (arrow) arrow.position.copy(centroid(i)).addScaledVector(up, 0.9 * reach).addScaledVector(left, 0.9 * reach);
      follow(i);
      panel.time.textContent = 't = ' + times[i].toFixed(3) + ' ' + data.time_unit;
      panel.sample.textContent = '(sample ' + (i + 1) + ' of ' + n + ')';
      for (let k = 0; k < columns; k++) panel.values[k].textContent = short(values[i * columns + k]);
      controlsBar.slider.value = String(i);
      shown = i;
    };

    const resize = () => {
      const width = view.clientWidth;
      const height = view.clientHeight;
      renderer.setSize(width, height, false);
      camera.aspect = width / height;
      camera.updateProjectionMatrix();
      dirty = true;
    };
    window.addEventListener('resize', resize);
    resize();

    const publish = () => {
      const rect = renderer.domElement.getBoundingClientRect();
      const output = panel.output;
      output.dataset.sample = String(shown);
      output.dataset.time = String(times[shown]);
      output.dataset.view = camera.matrixWorldInverse.elements.join(' ');
      output.dataset.projection = camera.projectionMatrix.elements.join(' ');
      output.dataset.viewport = [rect.left, rect.top, rect.width, rect.height].join(' ');
      output.dataset.pixelRatio = String(window.devicePixelRatio || 1);
    };

    const setPlaying = (on) => {
      playing = on && n > 1;
      controlsBar.play.textContent = playing ? 'Pause' : 'Play';
      previous = null;
    };
    controlsBar.play.addEventListener('click', () => {
      if (!playing && clock >= last) clock = first;
      setPlaying(!playing);
    });
    controlsBar.slider.addEventListener('input', () => {
      clock = times[Number(controlsBar.slider.value)];
      dirty = true;
    });
    controlsBar.follow.addEventListener('change', () => { dirty = true; });
    controls.addEventListener('change', () => { dirty = true; });
    window.addEventListener('keydown', (event) => {
      if (event.target instanceof HTMLInputElement || event.target instanceof HTMLSelectElement) return;
      if (event.key === ' ') {
        event.preventDefault();
        controlsBar.play.click();
      } else if (event.key === 'ArrowRight' || event.key === 'ArrowLeft') {
        setPlaying(false);
        const i = Math.min(Math.max(shown + (event.key === 'ArrowRight' ? 1 : -1), 0), n - 1);
        clock = times[i];
        dirty = true;
      }
    });
    window.addEventListener('hashchange', () => {
      const next = fragment();
      if (next.t !== null) clock = Math.min(Math.max(next.t, first), last);
      setPlaying(!next.pause);
      dirty = true;
    });

    // Frame timing, for `measure`: the interval between frames and the time spent drawing.
    let timing = null;

    const frame = (now) => {
      const began = performance.now();
      if (playing && previous !== null) {
        clock += ((now - previous) / 1000) * Number(controlsBar.speed.value);
        if (clock > last) {
          if (controlsBar.loop.checked) {
            clock = first + ((clock - first) % Math.max(last - first, 1e-9));
          } else {
            clock = last;
            setPlaying(false);
          }
        }
      }
      previous = playing ? now : null;
      const i = sampleAt(clock);
      if (i !== shown || dirty) {
        show(i);
        renderer.render(scene, camera);
        publish();
        dirty = false;
      }
      if (timing) {
        if (timing.last !== null) {
          timing.intervals.push(now - timing.last);
          timing.drawing.push(performance.now() - began);
        }
        timing.last = now;
        if (timing.intervals.length >= timing.frames) {
          const done = timing;
          timing = null;
          done.resolve({ intervals: done.intervals, drawing: done.drawing });
        }
      }
      requestAnimationFrame(frame);
    };

    setPlaying(playing);
    show(sampleAt(clock));
    renderer.render(scene, camera);
    publish();
    dirty = false;
    requestAnimationFrame(frame);

    Object.assign(window.hamelScene, {
      state: () => ({
        sample: shown,
        time: times[shown],
        playing,
        view: Array.from(camera.matrixWorldInverse.elements),
        projection: Array.from(camera.projectionMatrix.elements),
        viewport: panel.output.dataset.viewport.split(' ').map(Number),
        pixelRatio: window.devicePixelRatio || 1,
      }),
      setTime: (t) => { clock = Math.min(Math.max(t, first), last); dirty = true; },
      play: () => setPlaying(true),
      pause: () => setPlaying(false),
      // Plays for `frames` frames and resolves with each frame's interval and drawing time
      // (milliseconds).
      measure: (frames) => new Promise((resolve) => {
        controlsBar.loop.checked = true;
        setPlaying(true);
        timing = { frames, intervals: [], drawing: [], last: null, resolve };
      }),
    });
    // Resolved once the first picture has reached the screen (two frames later).
    requestAnimationFrame(() => requestAnimationFrame(() => resolveReady(window.hamelScene.state())));
  }

  // The script runs at the end of the body, after the elements it uses.
  start().catch(fail);
})();
