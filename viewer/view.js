// The axonguide browser viewer: somas as instanced spheres, axons (or, in an arbour run,
// every cone's path) as line segments that grow with the time slider, cue sources and
// particle frames, an orbit camera, and a click on a soma to see the neuron. Arbour
// segments can be coloured by centrifugal order or by neurite type. Everything it shows comes from the JSON that
// `axonguide view` embeds in the page (element #axg-data); nothing is fetched.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/OrbitControls.js';

const STATUS = ['growing', 'connected', 'exited', 'max_steps'];
const STATUS_COLORS = [0x1f77b4, 0x2ca02c, 0xff7f0e, 0x9467bd];

const $ = (id) => document.getElementById(id);

function decode(b64, Type) {
  if (!b64) return null;
  const bin = atob(b64);
  const bytes = new Uint8Array(bin.length);
  for (let i = 0; i < bin.length; ++i) bytes[i] = bin.charCodeAt(i);
  return new Type(bytes.buffer);
}

// A stable, well-spread colour for an integer label (components).
function labelColor(label, out) {
  const h = ((label * 0.6180339887498949) % 1 + 1) % 1;
  return out.setHSL(h, 0.65, 0.5);
}

function levelColor(level, maxLevel, out) {
  if (level < 0) return out.setRGB(0.55, 0.55, 0.55);
  const t = maxLevel > 0 ? level / maxLevel : 0;
  return out.setHSL(0.66 * (1 - t), 0.8, 0.5);
}

// Centrifugal order 0, 1, 2, ... from blue through green to red (order >= 8 is red).
const MAX_ORDER_HUE = 8;
function orderColor(order, out) {
  return out.setHSL(0.66 * (1 - Math.min(order, MAX_ORDER_HUE) / MAX_ORDER_HUE), 0.85, 0.55);
}
const TYPE_COLORS = { 2: 0xff6b4a, 3: 0x4ab0ff };  // SWC types: axon, dendrite

function legendHtml(mode) {
  const swatch = (css, label) => `<span style="background:${css}"></span>${label}`;
  if (mode === 'type') return swatch('#ff6b4a', 'axon') + swatch('#4ab0ff', 'dendrite');
  if (mode === 'order') {
    const c = new THREE.Color();
    return [0, 1, 2, 4, MAX_ORDER_HUE].map((o) => swatch(`#${orderColor(o, c).getHexString()}`,
      o === MAX_ORDER_HUE ? `${o}+` : `${o}`)).join('') + ' order';
  }
  return swatch('#1f77b4', 'growing') + swatch('#2ca02c', 'connected') + swatch('#ff7f0e', 'exited') +
    swatch('#9467bd', 'max steps');
}

function main() {
  const raw = JSON.parse($('axg-data').textContent);
  const meta = raw.meta;
  const n = meta.neurons;
  const soma = decode(raw.soma, Float32Array);
  const status = decode(raw.status, Uint8Array);
  const steps = decode(raw.steps, Uint32Array);
  const target = decode(raw.target, Int32Array);
  const length = decode(raw.length, Float32Array);
  const level = decode(raw.level, Int32Array);
  const component = decode(raw.component, Int32Array);
  const maxLevel = level ? level.reduce((m, v) => Math.max(m, v), 0) : 0;

  // (Missing files and thinning are listed in #axg-notes by `axonguide view`.)
  $('axg-title').textContent = meta.title;

  const renderer = new THREE.WebGLRenderer({ antialias: n < 20000, preserveDrawingBuffer: true });
  renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
  renderer.setSize(window.innerWidth, window.innerHeight);
  renderer.setClearColor(0x0b0e14);
  $('axg-canvas').appendChild(renderer.domElement);

  const scene = new THREE.Scene();
  const extent = meta.extent;
  const camera = new THREE.PerspectiveCamera(45, window.innerWidth / window.innerHeight, extent * 0.01, extent * 20);
  camera.position.set(extent * 1.6, extent * 1.2, extent * 2.0);
  const controls = new OrbitControls(camera, renderer.domElement);
  controls.enableDamping = true;
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  const light = new THREE.DirectionalLight(0xffffff, 1.6);
  light.position.set(1, 2, 3);
  scene.add(light);

  // Somas: one instanced mesh (one draw call for any n).
  const detail = n > 20000 ? 0 : 1;
  const sphere = new THREE.IcosahedronGeometry(meta.soma_radius, detail);
  const somas = new THREE.InstancedMesh(sphere, new THREE.MeshLambertMaterial(), n);
  const m = new THREE.Matrix4();
  for (let i = 0; i < n; ++i) {
    m.makeTranslation(soma[3 * i], soma[3 * i + 1], soma[3 * i + 2]);
    somas.setMatrixAt(i, m);
  }
  somas.instanceMatrix.needsUpdate = true;
  scene.add(somas);

  // Axons: segments with the step at which each one is drawn; a shader hides the future.
  const seg = raw.paths;
  const segPos = decode(seg.points, Float32Array);
  const segStep = decode(seg.step, Float32Array);
  const segOwner = decode(seg.owner, Uint32Array);
  const segType = decode(raw.paths_type, Uint8Array);  // arbour runs only
  const segOrder = decode(raw.paths_order, Uint8Array);
  const axonGeo = new THREE.BufferGeometry();
  axonGeo.setAttribute('position', new THREE.BufferAttribute(segPos, 3));
  axonGeo.setAttribute('step', new THREE.BufferAttribute(segStep, 1));
  const axonColor = new Float32Array(segPos.length);
  axonGeo.setAttribute('color', new THREE.BufferAttribute(axonColor, 3));
  const axonMat = new THREE.ShaderMaterial({
    uniforms: { uTime: { value: 0 } },
    vertexShader: `attribute float step; attribute vec3 color; varying float vStep; varying vec3 vColor;
      void main() { vStep = step; vColor = color; gl_Position = projectionMatrix * modelViewMatrix * vec4(position, 1.0); }`,
    fragmentShader: `uniform float uTime; varying float vStep; varying vec3 vColor;
      void main() { if (vStep > uTime) discard; gl_FragColor = vec4(vColor, 1.0); }`,
  });
  const axons = new THREE.LineSegments(axonGeo, axonMat);
  scene.add(axons);

  // Sources.
  const sources = new THREE.Group();
  for (const s of raw.sources) {
    const mesh = new THREE.Mesh(new THREE.SphereGeometry(meta.soma_radius * 2.2, 16, 12),
      new THREE.MeshLambertMaterial({ color: s.kind === 'attractant' ? 0x33dd55 : 0xee3333, emissive: 0x222222 }));
    mesh.position.set(s.x, s.y, s.z);
    sources.add(mesh);
  }
  scene.add(sources);

  // Particle frames: one Points object each, shown for the frame at or before the time.
  const frames = raw.frames.map((f) => {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(decode(f.pos, Float32Array), 3));
    const cue = decode(f.cue, Uint8Array);
    const c = new Float32Array(cue.length * 3);
    const col = new THREE.Color();
    for (let i = 0; i < cue.length; ++i) {
      const s = raw.sources[cue[i]];
      col.set(s && s.kind === 'attractant' ? 0x77ff99 : 0xff7777);
      c[3 * i] = col.r; c[3 * i + 1] = col.g; c[3 * i + 2] = col.b;
    }
    g.setAttribute('color', new THREE.BufferAttribute(c, 3));
    const p = new THREE.Points(g, new THREE.PointsMaterial({ size: meta.soma_radius * 0.35, vertexColors: true,
      transparent: true, opacity: 0.6, depthWrite: false }));
    p.visible = false;
    scene.add(p);
    return { step: f.step, points: p };
  });

  // Colour of neuron i at time t in the current mode.
  const color = new THREE.Color();
  function neuronColor(i, t) {
    const mode = $('axg-color').value;
    if ((mode === 'order' || mode === 'type') && segOrder) return color.setRGB(0.85, 0.85, 0.85);
    if (mode === 'component' && component) return labelColor(component[i], color);
    if (mode === 'level' && level) return levelColor(level[i], maxLevel, color);
    const s = steps[i] > t ? 0 : status[i];
    return color.setHex(STATUS_COLORS[s]);
  }

  const slider = $('axg-time');
  slider.max = meta.steps_run;
  let time = meta.steps_run;
  let coloredAt = null;  // (step, mode) the colours were last computed for
  function setTime(t) {
    time = Math.max(0, Math.min(meta.steps_run, t));
    slider.value = time;
    $('axg-step').textContent = `step ${Math.floor(time)} / ${meta.steps_run}`;
    axonMat.uniforms.uTime.value = time;
    const ti = Math.floor(time);
    const key = `${ti} ${$('axg-color').value}`;
    updateFrames();
    if (key === coloredAt) return;  // while playing, colours change only at whole steps
    coloredAt = key;
    for (let i = 0; i < n; ++i) somas.setColorAt(i, neuronColor(i, ti));
    somas.instanceColor.needsUpdate = true;
    const mode = $('axg-color').value;
    const bySegment = segOrder && (mode === 'order' || mode === 'type');
    $('axg-legend').innerHTML = legendHtml(bySegment ? mode : 'status');
    for (let k = 0; k < segOwner.length; ++k) {
      if (bySegment && mode === 'order') orderColor(segOrder[k], color);
      else if (bySegment) color.setHex(TYPE_COLORS[segType[k]]);
      else neuronColor(segOwner[k], ti);
      for (let v = 0; v < 2; ++v) {
        axonColor[6 * k + 3 * v] = color.r; axonColor[6 * k + 3 * v + 1] = color.g; axonColor[6 * k + 3 * v + 2] = color.b;
      }
    }
    axonGeo.attributes.color.needsUpdate = true;
  }
  function updateFrames() {
    let shown = -1;
    frames.forEach((f, k) => { if (f.step <= time) shown = k; });
    frames.forEach((f, k) => { f.points.visible = k === shown && $('axg-particles').checked; });
  }
  slider.addEventListener('input', () => setTime(Number(slider.value)));
  $('axg-color').addEventListener('change', () => { coloredAt = null; setTime(time); });
  $('axg-axons').addEventListener('change', () => { axons.visible = $('axg-axons').checked; });
  $('axg-sources').addEventListener('change', () => { sources.visible = $('axg-sources').checked; });
  $('axg-particles').addEventListener('change', () => setTime(time));
  if (!component) $('axg-color').querySelector('option[value=component]').disabled = true;
  if (!level) $('axg-color').querySelector('option[value=level]').disabled = true;
  for (const v of ['order', 'type']) $('axg-color').querySelector(`option[value=${v}]`).disabled = !segOrder;
  if (segOrder) $('axg-color').value = 'order';
  if (!raw.frames.length) $('axg-particles-label').style.display = 'none';

  let playing = false;
  let last = 0;
  $('axg-play').addEventListener('click', () => {
    playing = !playing;
    $('axg-play').textContent = playing ? 'pause' : 'play';
    if (playing && time >= meta.steps_run) setTime(0);
    last = performance.now();
  });

  // Click a soma: its id, status, target, level, component and path length.
  const raycaster = new THREE.Raycaster();
  const pointer = new THREE.Vector2();
  let downAt = null;
  renderer.domElement.addEventListener('pointerdown', (e) => { downAt = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (!downAt || Math.hypot(e.clientX - downAt[0], e.clientY - downAt[1]) > 4) return;
    pointer.set((e.clientX / window.innerWidth) * 2 - 1, -(e.clientY / window.innerHeight) * 2 + 1);
    raycaster.setFromCamera(pointer, camera);
    const hit = raycaster.intersectObject(somas)[0];
    if (!hit) return;
    showNeuron(hit.instanceId);
  });
  function showNeuron(i) {
    const lines = [
      `<b>neuron ${i}</b>`,
      `status: ${STATUS[status[i]]} at step ${steps[i]}`,
      `target: ${target[i] >= 0 ? target[i] : 'none'}`,
      `BFS level: ${level ? level[i] : 'n/a'}`,
      `component: ${component ? component[i] : 'n/a'}`,
      `path length: ${length[i].toFixed(3)} LU`,
      `soma: (${soma[3 * i].toFixed(2)}, ${soma[3 * i + 1].toFixed(2)}, ${soma[3 * i + 2].toFixed(2)})`,
    ];
    $('axg-info').innerHTML = lines.join('<br>');
  }
  window.axgShowNeuron = showNeuron;

  window.addEventListener('resize', () => {
    camera.aspect = window.innerWidth / window.innerHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(window.innerWidth, window.innerHeight);
  });

  setTime(meta.steps_run);
  let frameCount = 0;
  let fpsFrames = 0, fpsSince = performance.now(), summary = '';
  function animate(now) {
    requestAnimationFrame(animate);
    if (playing) {
      const rate = Math.max(5, meta.steps_run / 8);  // the whole run in about 8 s
      setTime(time + ((now - last) / 1000) * rate);
      last = now;
      if (time >= meta.steps_run) { playing = false; $('axg-play').textContent = 'play'; }
    }
    controls.update();
    renderer.render(scene, camera);
    if (++frameCount === 2) {
      summary = `ready: ${n} neurons, ${segOwner.length} ${segOrder ? 'arbour' : 'axon'} segments, ${raw.sources.length} sources, ${frames.length} particle frames`;
      $('axg-status').textContent = summary;
      document.body.dataset.ready = '1';
      console.log('axonguide view ready');
    }
    ++fpsFrames;
    if (frameCount > 2 && now - fpsSince > 1000) {
      $('axg-status').textContent = `${summary}; ${(fpsFrames * 1000 / (now - fpsSince)).toFixed(0)} frames/s`;
      fpsFrames = 0;
      fpsSince = now;
    }
  }
  requestAnimationFrame(animate);
}

try {
  main();
} catch (e) {
  $('axg-status').textContent = `error: ${e && e.message ? e.message : e}`;
  throw e;
}
