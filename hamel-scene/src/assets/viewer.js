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
  // The colour of a wheel's hub (the browser test looks for it at the wheel's centre).
  const HUB = 0x1a1a1a;
  // The triads' colours, as in the pictures: x red, y green, z blue.
  const TRIAD = [0xd62728, 0x2ca02c, 0x1f77b4];

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

  // The samples: times, and per sample the bodies' poses (centre, quaternion), the contact
  // points and the shown columns' values.
  function samplesOf(data) {
    const times = decode(data.times, Float64Array);
    return {
      times,
      n: times.length,
      poses: decode(data.poses, Float32Array),
      points: decode(data.points, Float32Array),
      values: decode(data.values, Float64Array),
      bodies: data.bodies.length,
      contacts: data.contacts.length,
      columns: data.columns.length,
    };
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
  function brief(x) {
    const text = short(x);
    return text.includes('.') && !text.includes('e') ? text.replace(/\.?0+$/, '') : text;
  }

  const css = (color) => '#' + color.toString(16).padStart(6, '0');

  // A wheel: sectors of two colours round a dark hub, so that the spin shows, and a tyre.
  // The face is one mesh with a colour per vertex: in software rendering each draw call
  // costs more than its pixels.
  function disk(THREE, body) {
    const r = body.solid.radius;
    const hub = 0.15 * r;
    const colors = [new THREE.Color(body.color), new THREE.Color(body.color).multiplyScalar(0.55), new THREE.Color(HUB)];
    const segments = 48;
    const sectors = 8;
    const position = [];
    const color = [];
    const corner = (radius, k) => {
      const angle = (2 * Math.PI * k) / segments;
      return [radius * Math.cos(angle), radius * Math.sin(angle), 0];
    };
    const triangle = (a, b, c, paint) => {
      position.push(...a, ...b, ...c);
      for (let v = 0; v < 3; v++) color.push(paint.r, paint.g, paint.b);
    };
    for (let k = 0; k < segments; k++) {
      const paint = colors[Math.floor((k * sectors) / segments) % 2];
      const [i0, i1, o0, o1] = [corner(hub, k), corner(hub, k + 1), corner(r, k), corner(r, k + 1)];
      triangle([0, 0, 0], i0, i1, colors[2]);
      triangle(i0, o0, o1, paint);
      triangle(i0, o1, i1, paint);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(position, 3));
    geometry.setAttribute('color', new THREE.Float32BufferAttribute(color, 3));
    const face = new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide });
    const tyre = new THREE.MeshLambertMaterial({ color: 0x444444 });
    const group = new THREE.Group().add(
      new THREE.Mesh(geometry, face),
      new THREE.Mesh(new THREE.TorusGeometry(r, 0.035 * r, 6, 48), tyre),
    );
    // The face and the tyre lie in the xy plane: turn their normal, z, onto the axle.
    group.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), new THREE.Vector3(...body.solid.axis).normalize());
    return group;
  }

  // A ball: lunes of two colours, so that the rotation shows (one mesh, a colour per
  // triangle).
  function ball(THREE, body) {
    const geometry = new THREE.SphereGeometry(body.solid.radius, 32, 16).toNonIndexed();
    const colors = [new THREE.Color(body.color), new THREE.Color(body.color).multiplyScalar(0.55)];
    const position = geometry.getAttribute('position');
    const color = new Float32Array(position.count * 3);
    for (let t = 0; t < position.count; t += 3) {
      // The lune of the triangle's centre, by its longitude about y (the sphere's axis).
      let x = 0;
      let z = 0;
      for (let v = t; v < t + 3; v++) {
        x += position.getX(v);
        z += position.getZ(v);
      }
      const longitude = Math.atan2(z, x) + Math.PI;
      const paint = colors[Math.floor((longitude / (2 * Math.PI)) * 8) % 2];
      for (let v = t; v < t + 3; v++) color.set([paint.r, paint.g, paint.b], 3 * v);
    }
    geometry.setAttribute('color', new THREE.BufferAttribute(color, 3));
    return new THREE.Mesh(geometry, new THREE.MeshLambertMaterial({ vertexColors: true }));
  }

  // A body's axes: three lines from its centre, x red, y green, z blue (one draw call).
  function triad(THREE, length) {
    const position = [];
    const color = [];
    TRIAD.forEach((hex, k) => {
      const end = [0, 0, 0];
      end[k] = length;
      position.push(0, 0, 0, ...end);
      const paint = new THREE.Color(hex);
      color.push(paint.r, paint.g, paint.b, paint.r, paint.g, paint.b);
    });
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(position, 3));
    geometry.setAttribute('color', new THREE.Float32BufferAttribute(color, 3));
    return new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: true }));
  }

  // A body's solid, in its own axes.
  function solidOf(THREE, body) {
    const solid = body.solid;
    const lit = new THREE.MeshLambertMaterial({ color: body.color });
    let object;
    if (solid.kind === 'disk') {
      object = disk(THREE, body);
    } else if (solid.kind === 'sphere') {
      object = ball(THREE, body);
    } else if (solid.kind === 'marker') {
      object = new THREE.Mesh(new THREE.SphereGeometry(solid.radius, 16, 12), lit);
    } else if (solid.kind === 'ellipsoid') {
      const mesh = new THREE.Mesh(new THREE.SphereGeometry(1, 32, 20), lit);
      mesh.scale.set(...solid.semi_axes);
      object = new THREE.Group().add(mesh);
      object.quaternion.set(...solid.rotation);
    } else if (solid.kind === 'box') {
      const geometry = new THREE.BoxGeometry(...solid.edges);
      const edges = new THREE.LineSegments(new THREE.EdgesGeometry(geometry), new THREE.LineBasicMaterial({ color: 0x333333 }));
      object = new THREE.Group().add(new THREE.Mesh(geometry, lit), edges);
      object.quaternion.set(...solid.rotation);
    } else if (solid.kind === 'cylinder') {
      object = new THREE.Mesh(new THREE.CylinderGeometry(solid.radius, solid.radius, solid.length, 32), lit);
      // Cylinders lie along y.
      object.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), new THREE.Vector3(...solid.axis).normalize());
    } else {
      throw new Error('unknown solid ' + solid.kind);
    }
    const placed = new THREE.Group().add(object);
    placed.position.set(...body.offset);
    return placed;
  }

  // A plane's grid: one square in the plane's own xy, its lines drawn by the fragment shader
  // where the square's points lie on them (a line as wide as a pixel, at any distance). Not
  // line primitives: software WebGL (SwiftShader) drops a line whose end is behind the
  // camera, and on a long run every line of a grid under the whole motion has one there, so
  // the ground vanished. The lines through the grid's centre are darker; where lines are
  // closer than a few pixels (towards the horizon) they fade, rather than shimmer.
  function gridOf(THREE, grid) {
    const grey = (v) => new THREE.Vector3(v / 255, v / 255, v / 255);
    const material = new THREE.ShaderMaterial({
      uniforms: {
        spacing: { value: grid.step },
        minor: { value: grey(0xd4) },
        major: { value: grey(0xaa) },
      },
      vertexShader: `
        varying vec2 local;
        void main() {
          local = position.xy;
          gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0);
        }`,
      fragmentShader: `
        uniform float spacing;
        uniform vec3 minor;
        uniform vec3 major;
        varying vec2 local;
        // How much of this pixel a line of the lattice spaced 1 apart in c covers.
        float lines(vec2 c) {
          vec2 d = abs(fract(c - 0.5) - 0.5) / fwidth(c);
          return 1.0 - min(min(d.x, d.y), 1.0);
        }
        void main() {
          vec2 cells = local / spacing;
          vec2 perPixel = fwidth(cells);
          float fade = 1.0 - smoothstep(0.15, 0.45, max(perPixel.x, perPixel.y));
          float minorLines = lines(cells) * fade;
          vec2 d = abs(local) / fwidth(local);
          float centreLines = 1.0 - min(min(d.x, d.y), 1.0);
          float alpha = max(minorLines, centreLines);
          if (alpha <= 0.0) discard;
          gl_FragColor = vec4(mix(minor, major, centreLines), alpha);
        }`,
      transparent: true,
      depthWrite: false,
      side: THREE.DoubleSide,
      // Behind what lies in the plane (the contacts' traces).
      polygonOffset: true,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    const square = new THREE.Mesh(new THREE.PlaneGeometry(grid.size, grid.size), material);
    square.position.set(grid.centre[0], grid.centre[1], 0);
    return square;
  }

  // A surface the contacts touch, where the model puts it: a plane as a grid in its own
  // plane, a sphere as a sphere, a bowl as the inside of one, both faint so that what rolls
  // on them shows.
  function surfaceOf(THREE, surface) {
    if (surface.kind === 'plane') {
      const grid = gridOf(THREE, surface.grid);
      const plane = new THREE.Group().add(grid);
      plane.position.set(...surface.origin);
      plane.quaternion.set(...surface.rotation);
      return plane;
    }
    if (surface.kind === 'sphere' || surface.kind === 'bowl') {
      const material = new THREE.MeshLambertMaterial({
        color: 0xb8b8b8, transparent: true, opacity: surface.kind === 'bowl' ? 0.25 : 0.5,
        side: surface.kind === 'bowl' ? THREE.BackSide : THREE.FrontSide, depthWrite: false,
      });
      const sphere = new THREE.Mesh(new THREE.SphereGeometry(surface.radius, 48, 24), material);
      const lines = new THREE.LineSegments(new THREE.WireframeGeometry(new THREE.SphereGeometry(surface.radius, 24, 12)),
        new THREE.LineBasicMaterial({ color: 0x999999, transparent: true, opacity: 0.5 }));
      const group = new THREE.Group().add(sphere, lines);
      group.position.set(...surface.centre);
      return group;
    }
    throw new Error('unknown surface ' + surface.kind);
  }

  // The farthest a surface's drawing reaches from the origin: what the camera must see.
  function surfaceReach(surface) {
    const norm = (v) => Math.hypot(...v);
    if (surface.kind === 'plane') {
      return norm(surface.origin) + norm(surface.grid.centre) + surface.grid.size;
    }
    return norm(surface.centre) + surface.radius;
  }

  // The renderer, the scene with its lights and the surfaces, and the camera.
  function world(THREE, data, directions) {
    // No multisampling: in software rendering (SwiftShader, a machine without a GPU) it
    // costs a frame of 16.7 ms or more, for smoother edges only (tests/browser/README.md).
    const renderer = new THREE.WebGLRenderer({ antialias: false });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    document.getElementById('view').appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xf4f4f4);
    const reach = data.radius;
    const far = Math.max(...data.surfaces.map(surfaceReach));
    const camera = new THREE.PerspectiveCamera(35, 1, reach / 100, reach * 1000 + far * 4);
    camera.up.copy(directions.up);
    const sky = new THREE.HemisphereLight(0xffffff, 0x999999, 2.2);
    sky.position.copy(directions.up);
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.copy(directions.up.clone().multiplyScalar(3).sub(directions.left).add(directions.forward));
    scene.add(sky, sun, ...data.surfaces.map((s) => surfaceOf(THREE, s)));
    return { renderer, scene, camera };
  }

  // The bodies, each with its axes as a triad, and each contact's trace on the
  // ground (drawn up to the shown sample) with a dot where it is.
  function things(THREE, data, samples, scene) {
    const bodies = data.bodies.map((body) => {
      const group = new THREE.Group().add(solidOf(THREE, body), triad(THREE, body.triad));
      scene.add(group);
      return group;
    });
    const { n, contacts, points } = samples;
    const traces = data.contacts.map((contact, j) => {
      const line = new Float32Array(3 * n);
      for (let i = 0; i < n; i++) {
        const at = 3 * (i * contacts + j);
        line.set(points.subarray(at, at + 3), 3 * i);
      }
      const geometry = new THREE.BufferGeometry();
      geometry.setAttribute('position', new THREE.BufferAttribute(line, 3));
      const color = contact.body === null ? 0x333333 : new THREE.Color(data.bodies[contact.body].color).multiplyScalar(0.6);
      const trace = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color }));
      const dot = new THREE.Mesh(new THREE.SphereGeometry(0.02 * data.radius, 12, 8), new THREE.MeshBasicMaterial({ color: 0x000000 }));
      scene.add(trace, dot);
      return { trace, dot };
    });
    let arrow = null;
    if (data.gravity) {
      const r = data.radius;
      arrow = new THREE.ArrowHelper(new THREE.Vector3(...data.gravity).normalize(), new THREE.Vector3(), 0.6 * r, 0x555555, 0.15 * r, 0.08 * r);
      scene.add(arrow);
    }
    return { bodies, traces, arrow };
  }

  // The panel beside the scene: a row per shown column, the bodies and what they are drawn
  // as, gravity, and the warnings. Returns what changes with the sample.
  function panel(data) {
    const table = document.getElementById('values');
    const cells = data.columns.map((column) => {
      const row = table.insertRow();
      row.insertCell().textContent = column.name;
      const value = row.insertCell();
      value.className = 'value';
      row.insertCell().textContent = column.unit || '';
      return value;
    });
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
    return {
      time: document.getElementById('time'),
      sample: document.getElementById('sample'),
      cells,
      camera: document.getElementById('camera'),
    };
  }

  // The controls under the scene, set from the fragment.
  function controlsFrom(options, n) {
    const controls = {
      play: document.getElementById('play'),
      speed: document.getElementById('speed'),
      slider: document.getElementById('slider'),
      loop: document.getElementById('loop'),
      follow: document.getElementById('follow'),
    };
    controls.slider.max = String(n - 1);
    if (options.speed !== null) {
      const option = document.createElement('option');
      option.value = String(options.speed);
      option.textContent = options.speed + '×';
      controls.speed.append(option);
      controls.speed.value = String(options.speed);
    }
    if (options.follow !== null) controls.follow.checked = options.follow;
    return controls;
  }

  // The camera looks at the mechanism's first sample from its right, ahead and above, and
  // orbits about it.
  function aim(THREE, OrbitControls, view, directions, origin, reach) {
    const azimuth = (35 * Math.PI) / 180;
    const elevation = (22 * Math.PI) / 180;
    const direction = directions.left.clone().multiplyScalar(-Math.cos(azimuth))
      .addScaledVector(directions.forward, Math.sin(azimuth))
      .multiplyScalar(Math.cos(elevation))
      .addScaledVector(directions.up, Math.sin(elevation));
    view.camera.position.copy(origin).addScaledVector(direction, 6 * reach);
    const orbit = new OrbitControls(view.camera, view.renderer.domElement);
    orbit.target.copy(origin);
    orbit.update();
    return orbit;
  }

  async function start() {
    const data = JSON.parse(document.getElementById('hamel-data').textContent);
    const { THREE, OrbitControls } = await loadThree();
    document.getElementById('three-version').textContent = 'r' + THREE.REVISION;
    const samples = samplesOf(data);
    const vector = (a) => new THREE.Vector3(a[0], a[1], a[2]);
    const directions = { up: vector(data.up), forward: vector(data.forward), left: vector(data.left) };
    const view = world(THREE, data, directions);
    const drawn = things(THREE, data, samples, view.scene);
    const options = fragment();
    for (const b of options.hide) if (drawn.bodies[b]) drawn.bodies[b].visible = false;
    const centroid = (i) => {
      const c = new THREE.Vector3();
      for (let b = 0; b < samples.bodies; b++) {
        const at = 7 * (i * samples.bodies + b);
        c.x += samples.poses[at];
        c.y += samples.poses[at + 1];
        c.z += samples.poses[at + 2];
      }
      return c.multiplyScalar(1 / samples.bodies);
    };
    const orbit = aim(THREE, OrbitControls, view, directions, centroid(0), data.radius);
    const player = new Player(data, samples, view, drawn, panel(data), controlsFrom(options, samples.n), orbit, centroid, directions);
    player.begin(options);
  }

  // Playback. `clock` is the playback time; the sample shown is the last one at or before
  // it, so the frames are the samples as computed.
  class Player {
    constructor(data, samples, view, drawn, panel, controls, orbit, centroid, directions) {
      Object.assign(this, { data, samples, view, drawn, panel, controls, orbit, centroid, directions });
      const times = samples.times;
      this.first = times[0];
      this.last = times[samples.n - 1];
      this.origin = centroid(0);
      // The point the camera keeps its place to: the centroid of the sample shown when
      // following, else the first sample's. The camera and its target move with it, so that
      // a pan (right-drag), which moves them both, is kept.
      this.anchor = this.origin.clone();
      this.clock = this.first;
      this.playing = false;
      this.shown = -1;
      this.dirty = true;
      this.previous = null;
      this.timing = null;
      // The fraction of the canvas' resolution drawn while playing, and the recent frame
      // intervals it is chosen from.
      this.scale = 1;
      this.recent = [];
    }

    sampleAt(t) {
      const times = this.samples.times;
      let lo = 0;
      let hi = times.length - 1;
      if (t >= times[hi]) return hi;
      while (lo < hi) {
        const mid = (lo + hi + 1) >> 1;
        if (times[mid] <= t) lo = mid;
        else hi = mid - 1;
      }
      return lo;
    }

    setTime(t) {
      this.clock = Math.min(Math.max(t, this.first), this.last);
      this.dirty = true;
    }

    setPlaying(on) {
      this.playing = on && this.samples.n > 1;
      this.controls.play.textContent = this.playing ? 'Pause' : 'Play';
      this.previous = null;
      this.applyScale();
    }

    // Keeping real time where the browser draws without a GPU: when the median of 30 frame
    // intervals while playing exceeds 20 ms (a frame missed at 60 Hz), the canvas is drawn at
    // three quarters of its resolution, down to half, and shown stretched to its size. A
    // paused scene is drawn at full resolution.
    adapt(interval) {
      this.recent.push(interval);
      if (this.recent.length < 30) return;
      const median = this.recent.sort((a, b) => a - b)[15];
      this.recent = [];
      if (median > 20 && this.scale > 0.5) {
        this.scale = Math.max(0.5, 0.75 * this.scale);
        this.applyScale();
      }
    }

    applyScale() {
      const ratio = (window.devicePixelRatio || 1) * (this.playing ? this.scale : 1);
      if (this.view.renderer.getPixelRatio() !== ratio) {
        this.view.renderer.setPixelRatio(ratio);
        this.dirty = true;
      }
      const note = document.getElementById('resolution');
      note.hidden = this.scale === 1;
      note.textContent = 'Played at ' + Math.round(100 * this.scale) + ' % of the resolution to keep ' +
        'real time (this browser draws without a graphics processor); paused, at full resolution.';
    }

    // Places everything at sample i and writes the panel.
    show(i) {
      const { poses, points, values, bodies, contacts, columns, times } = this.samples;
      for (let b = 0; b < bodies; b++) {
        const at = 7 * (i * bodies + b);
        this.drawn.bodies[b].position.set(poses[at], poses[at + 1], poses[at + 2]);
        this.drawn.bodies[b].quaternion.set(poses[at + 3], poses[at + 4], poses[at + 5], poses[at + 6]);
      }
      for (let j = 0; j < contacts; j++) {
        this.drawn.traces[j].trace.geometry.setDrawRange(0, i + 1);
        const at = 3 * (i * contacts + j);
        this.drawn.traces[j].dot.position.set(points[at], points[at + 1], points[at + 2]);
      }
      const centre = this.centroid(i);
      const reach = this.data.radius;
      if (this.drawn.arrow) this.drawn.arrow.position.copy(centre).addScaledVector(this.directions.up, 0.9 * reach).addScaledVector(this.directions.left, 0.9 * reach);
      // The camera follows the mechanism's centroid, or stays on the first sample's: it moves
      // as far as that point moved since the last frame, wherever the user turned or panned it.
      const anchor = this.controls.follow.checked ? centre : this.origin;
      const shift = anchor.clone().sub(this.anchor);
      this.anchor.copy(anchor);
      this.orbit.target.add(shift);
      this.view.camera.position.add(shift);
      this.orbit.update();
      this.panel.time.textContent = 't = ' + times[i].toFixed(3) + ' ' + this.data.time_unit;
      this.panel.sample.textContent = '(sample ' + (i + 1) + ' of ' + times.length + ')';
      for (let k = 0; k < columns; k++) this.panel.cells[k].textContent = short(values[i * columns + k]);
      this.controls.slider.value = String(i);
      this.shown = i;
    }

    resize() {
      const element = document.getElementById('view');
      this.view.renderer.setSize(element.clientWidth, element.clientHeight, false);
      this.view.camera.aspect = element.clientWidth / element.clientHeight;
      this.view.camera.updateProjectionMatrix();
      this.dirty = true;
    }

    // Draws, and publishes the camera that drew.
    render() {
      const { renderer, scene, camera } = this.view;
      renderer.render(scene, camera);
      const rect = renderer.domElement.getBoundingClientRect();
      const output = this.panel.camera;
      output.dataset.sample = String(this.shown);
      output.dataset.time = String(this.samples.times[this.shown]);
      output.dataset.view = camera.matrixWorldInverse.elements.join(' ');
      output.dataset.projection = camera.projectionMatrix.elements.join(' ');
      output.dataset.viewport = [rect.left, rect.top, rect.width, rect.height].join(' ');
      output.dataset.pixelRatio = String(window.devicePixelRatio || 1);
      this.dirty = false;
    }

    state() {
      const camera = this.view.camera;
      return {
        sample: this.shown,
        time: this.samples.times[this.shown],
        playing: this.playing,
        view: Array.from(camera.matrixWorldInverse.elements),
        projection: Array.from(camera.projectionMatrix.elements),
        viewport: this.panel.camera.dataset.viewport.split(' ').map(Number),
        pixelRatio: window.devicePixelRatio || 1,
        // The fraction of the resolution drawn while playing (below 1 where frames were slow).
        scale: this.scale,
        // What the camera looks at (the orbit's centre).
        target: this.orbit.target.toArray(),
      };
    }

    // One animation frame: advance the clock while playing, draw if anything changed, and
    // time the frame when measuring.
    frame(now) {
      const began = performance.now();
      if (this.playing && this.previous !== null) {
        this.adapt(now - this.previous);
        this.clock += ((now - this.previous) / 1000) * Number(this.controls.speed.value);
        if (this.clock > this.last) {
          if (this.controls.loop.checked) {
            this.clock = this.first + ((this.clock - this.first) % Math.max(this.last - this.first, 1e-9));
          } else {
            this.clock = this.last;
            this.setPlaying(false);
          }
        }
      }
      this.previous = this.playing ? now : null;
      const i = this.sampleAt(this.clock);
      if (i !== this.shown || this.dirty) {
        this.show(i);
        this.render();
      }
      this.time(now, began);
      requestAnimationFrame((t) => this.frame(t));
    }

    // Records the interval since the last frame and the time this one took, for `measure`.
    time(now, began) {
      const timing = this.timing;
      if (!timing) return;
      if (timing.last !== null) {
        timing.intervals.push(now - timing.last);
        timing.drawing.push(performance.now() - began);
      }
      timing.last = now;
      if (timing.intervals.length >= timing.frames) {
        this.timing = null;
        timing.resolve({ intervals: timing.intervals, drawing: timing.drawing });
      }
    }

    listen() {
      const c = this.controls;
      c.play.addEventListener('click', () => {
        if (!this.playing && this.clock >= this.last) this.clock = this.first;
        this.setPlaying(!this.playing);
      });
      c.slider.addEventListener('input', () => this.setTime(this.samples.times[Number(c.slider.value)]));
      c.follow.addEventListener('change', () => { this.dirty = true; });
      this.orbit.addEventListener('change', () => { this.dirty = true; });
      window.addEventListener('resize', () => this.resize());
      window.addEventListener('keydown', (event) => {
        if (event.target instanceof HTMLInputElement || event.target instanceof HTMLSelectElement) return;
        if (event.key === ' ') {
          event.preventDefault();
          c.play.click();
        } else if (event.key === 'ArrowRight' || event.key === 'ArrowLeft') {
          this.setPlaying(false);
          const step = event.key === 'ArrowRight' ? 1 : -1;
          this.setTime(this.samples.times[Math.min(Math.max(this.shown + step, 0), this.samples.n - 1)]);
        }
      });
      window.addEventListener('hashchange', () => {
        const next = fragment();
        if (next.t !== null) this.setTime(next.t);
        this.setPlaying(!next.pause);
      });
    }

    // Starts at the fragment's time, playing unless it says `pause`, and publishes the
    // page's interface.
    begin(options) {
      this.listen();
      this.resize();
      if (options.t !== null) this.setTime(options.t);
      this.setPlaying(!options.pause);
      this.show(this.sampleAt(this.clock));
      this.render();
      requestAnimationFrame((t) => this.frame(t));
      Object.assign(window.hamelScene, {
        state: () => this.state(),
        setTime: (t) => this.setTime(t),
        play: () => this.setPlaying(true),
        pause: () => this.setPlaying(false),
        // Plays for `frames` frames and resolves with each frame's interval and drawing
        // time (milliseconds).
        measure: (frames) => new Promise((resolve) => {
          this.controls.loop.checked = true;
          this.setPlaying(true);
          this.timing = { frames, intervals: [], drawing: [], last: null, resolve };
        }),
      });
      // Resolved once the first picture has reached the screen (two frames later).
      requestAnimationFrame(() => requestAnimationFrame(() => resolveReady(this.state())));
    }
  }

  // The script runs at the end of the body, after the elements it uses.
  start().catch(fail);
})();
