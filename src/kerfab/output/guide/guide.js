// kerfab assembly guide: the model in 3D, step by step in the assembly order kerfab computed
// (report.json: assembly.order). Data: model.js (window.KERFAB_MODEL, millimetres). No network.
(function () {
  'use strict';
  const M = window.KERFAB_MODEL;
  const $ = (id) => document.getElementById(id);
  const n = M.parts.length;
  const steps = M.steps;
  const stepOf = M.parts.map((p) => p.step - 1);  // 0-based step of each part
  const state = { step: 0, selected: -1 };
  const NEW = '#ff7f0e', SELECTED = '#1f6fd6';

  $('summary').innerHTML =
    `<b>${M.model}</b>: ${n} parts on ${M.sheets.length} sheet${M.sheets.length === 1 ? '' : 's'}` +
    (M.pieces > 1 ? `, in ${M.pieces} separate pieces` : '') +
    '. Each part carries its number, ' + (M.joint === 'glue tabs' ? 'printed.' : 'engraved.');
  $('rule').textContent = M.rule;

  // ---- 3D view ----
  let three = null;  // {renderer, scene, camera, controls, meshes, edges, labels}
  function message(text) { $('message').textContent = text; }
  function mix(hex, toward, t) {
    const a = new THREE.Color(hex), b = new THREE.Color(toward);
    return a.lerp(b, t);
  }
  function labelSprite(text, size) {
    const c = document.createElement('canvas');
    c.width = 128; c.height = 64;
    const g = c.getContext('2d');
    g.fillStyle = 'rgba(255,255,255,0.85)';
    g.fillRect(14, 8, 100, 48);
    g.font = 'bold 40px sans-serif';
    g.fillStyle = '#111';
    g.textAlign = 'center';
    g.textBaseline = 'middle';
    g.fillText(text, 64, 33);
    const tex = new THREE.CanvasTexture(c);
    const s = new THREE.Sprite(new THREE.SpriteMaterial({ map: tex, depthTest: true }));
    s.scale.set(size, size / 2, 1);
    return s;
  }
  function setUp3d() {
    if (!window.THREE || !THREE.OrbitControls) {
      message('three.js did not load: the steps and the sheets on the left still work.');
      return;
    }
    let renderer;
    try {
      renderer = new THREE.WebGLRenderer({ antialias: true });
    } catch (e) {
      message('This browser cannot draw 3D (WebGL is off): the steps and the sheets on the left still work.');
      return;
    }
    const view = $('view');
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0xffffff);
    view.insertBefore(renderer.domElement, view.firstChild);
    const scene = new THREE.Scene();
    const box = new THREE.Box3();
    const meshes = [], edges = [], labels = [];
    for (const p of M.parts) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(p.pos, 3));
      g.setIndex(p.tri);
      g.computeVertexNormals();
      g.computeBoundingBox();
      box.union(g.boundingBox);
      const m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({
        color: p.colour, side: THREE.DoubleSide,
        polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
      m.userData.part = p.n;
      scene.add(m);
      meshes.push(m);
      const eg = new THREE.BufferGeometry();
      eg.setAttribute('position', new THREE.Float32BufferAttribute(p.edges, 3));
      const e = new THREE.LineSegments(eg, new THREE.LineBasicMaterial({ color: 0x222222 }));
      scene.add(e);
      edges.push(e);
    }
    const centre = box.getCenter(new THREE.Vector3());
    const diag = box.getSize(new THREE.Vector3()).length() || 1;
    for (const p of M.parts) {
      const s = labelSprite(String(p.n), diag * 0.045);
      s.position.set(p.label[0], p.label[1], p.label[2]);
      scene.add(s);
      labels.push(s);
    }
    scene.add(new THREE.HemisphereLight(0xffffff, 0x666666, 0.75));
    const camera = new THREE.PerspectiveCamera(30, 1, diag / 100, diag * 20);
    const sun = new THREE.DirectionalLight(0xffffff, 0.55);
    sun.position.set(-1, 1, 2);
    camera.add(sun);
    scene.add(camera);
    // Model up along +y, seen from 35 degrees around and 10 degrees above: the view of kerfab's
    // pictures (pictures/*.png).
    const az = 35 * Math.PI / 180, el = 10 * Math.PI / 180, dist = diag * 1.75;
    camera.position.set(centre.x - dist * Math.cos(az) * Math.cos(el),
                        centre.y + dist * Math.sin(el),
                        centre.z - dist * Math.sin(az) * Math.cos(el));
    const controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.copy(centre);
    controls.update();
    three = { renderer, scene, camera, controls, meshes, edges, labels, diag };
    controls.addEventListener('change', render);
    window.addEventListener('resize', resize);
    // A click (not a drag) picks the part under the pointer.
    let down = null;
    renderer.domElement.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
    renderer.domElement.addEventListener('pointerup', (e) => {
      if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
      const r = renderer.domElement.getBoundingClientRect();
      const ray = new THREE.Raycaster();
      ray.setFromCamera(new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1,
                                          -((e.clientY - r.top) / r.height) * 2 + 1), camera);
      const hit = ray.intersectObjects(meshes.filter((m) => m.visible && m.material.opacity > 0.5));
      select(hit.length ? hit[0].object.userData.part : -1);
    });
    resize();
  }
  function resize() {
    if (!three) return;
    const v = $('view');
    three.renderer.setSize(v.clientWidth, v.clientHeight);
    three.camera.aspect = v.clientWidth / Math.max(1, v.clientHeight);
    three.camera.updateProjectionMatrix();
    render();
  }
  function render() { if (three) three.renderer.render(three.scene, three.camera); }

  // ---- state -> view ----
  function current() { return state.step > 0 ? steps[state.step - 1] : null; }
  function applyState() {
    const s = current();
    const joined = new Set(s ? s.joins.map((j) => j[0]) : []);
    const ghost = $('ghost').checked, showLabels = $('labels').checked;
    if (three) {
      for (const p of M.parts) {
        const m = three.meshes[p.n], mat = m.material, i = stepOf[p.n];
        let colour = new THREE.Color(p.colour), future = false;
        if (state.step > 0) {
          if (i === state.step - 1) colour = new THREE.Color(NEW);
          else if (i > state.step - 1) future = true;
          else if (!joined.has(p.n)) colour = mix(p.colour, '#e4e4e4', 0.75);
        }
        if (p.n === state.selected) colour = new THREE.Color(SELECTED);
        mat.color = colour;
        mat.transparent = future;
        mat.opacity = future ? 0.1 : 1;
        mat.depthWrite = !future;
        mat.needsUpdate = true;
        m.visible = !future || ghost;
        three.edges[p.n].visible = !future;
        three.labels[p.n].visible = showLabels && !future;
      }
      render();
    }
    $('stepno').textContent = state.step === 0 ? `finished model` : `step ${state.step} of ${steps.length}`;
    $('prev').disabled = state.step === 0;
    $('first').disabled = state.step === 0;
    $('next').disabled = state.step === steps.length;
    $('last').disabled = state.step === steps.length;
    document.body.dataset.step = String(state.step);
    document.body.dataset.highlighted = s ? String(s.part) : '';
    document.body.dataset.selected = state.selected >= 0 ? String(state.selected) : '';
    $('stepinfo').innerHTML = s ? stepText(s) :
      `All ${n} parts in place. Press <b>next</b> (or the right arrow key) to build it part by part.`;
    drawSheet();
  }
  function partLink(q) { return `<a class="part" data-part="${q}">${q}</a>`; }
  function contactText(c) {
    return `${partLink(c[0])} (${c[1].toFixed(0)} mm` + (c[2] > 0 ? `, ${c[2].toFixed(0)} mm with ${M.joint || 'teeth or tabs'})` : ', plain)');
  }
  function sheetText(p) { return p.sheet > 0 ? `sheet ${p.sheet}` : 'no sheet (it did not fit; see the report)'; }
  function stepText(s) {
    const p = M.parts[s.part];
    let t = `<span class="new">Part ${s.part}</span>, from ${sheetText(p)}. `;
    if (s.new_piece) t += state.step === 1 ? 'Start with it: it is the largest part.' :
      'Nothing placed touches it: it starts a separate piece.';
    else t += 'Glue it to: ' + s.joins.map(contactText).join(', ') + '.';
    if (s.closing) t += ' It fills a hole: every border it has meets parts already placed.';
    const later = p.neighbours.filter((c) => stepOf[c[0]] > state.step - 1).map((c) => partLink(c[0]));
    if (later.length) t += ` Later it also joins ${later.join(', ')}.`;
    return t;
  }
  function select(q) {
    state.selected = q;
    if (q < 0) { $('partinfo').innerHTML = ''; applyState(); return; }
    const p = M.parts[q];
    $('partinfo').innerHTML =
      `<span class="sel">Part ${q}</span>: ${sheetText(p)}, step ${p.step} of ${steps.length}, ` +
      `${Math.round(p.area)} mm&sup2;. <button id="gostep">go to its step</button>` +
      `<br>Neighbours: <ul>${p.neighbours.map((c) => '<li>' + contactText(c) + '</li>').join('')}</ul>`;
    $('gostep').onclick = () => go(p.step);
    applyState();
  }
  function go(k) {
    state.step = Math.max(0, Math.min(steps.length, k));
    applyState();
  }

  // ---- sheet preview ----
  let sheetPaths = [];
  function drawSheet() {
    const c = $('sheet'), g = c.getContext('2d');
    const focus = state.selected >= 0 ? state.selected : (current() ? current().part : -1);
    const sheetNo = focus >= 0 ? M.parts[focus].sheet : (M.sheets.length ? 1 : 0);
    g.clearRect(0, 0, c.width, c.height);
    sheetPaths = [];
    if (sheetNo <= 0) {
      $('sheettitle').textContent = 'Sheet';
      $('sheetcaption').textContent = focus >= 0 ? `Part ${focus} is on no sheet.` : '';
      return;
    }
    const sh = M.sheets[sheetNo - 1];
    const scale = Math.min((c.width - 4) / sh.w, (c.height - 4) / sh.h);
    c.height = Math.round(sh.h * scale + 4);
    g.fillStyle = '#f4efe4';
    g.fillRect(2, 2, sh.w * scale, sh.h * scale);
    const stepPart = current() ? current().part : -1;
    for (const on of sh.parts) {
      const path = new Path2D();
      for (let k = 0; k < on.outline.length; k += 2) {
        const x = 2 + on.outline[k] * scale, y = 2 + (sh.h - on.outline[k + 1]) * scale;
        if (k === 0) path.moveTo(x, y); else path.lineTo(x, y);
      }
      path.closePath();
      sheetPaths.push([on.part, path]);
      const placed = state.step > 0 && stepOf[on.part] < state.step - 1;
      g.fillStyle = on.part === state.selected ? SELECTED : on.part === stepPart ? NEW : placed ? '#c9c9c9' : '#ffffff';
      g.fill(path);
      g.strokeStyle = '#555';
      g.lineWidth = 0.7;
      g.stroke(path);
    }
    $('sheettitle').textContent = `Sheet ${sheetNo} of ${M.sheets.length}`;
    $('sheetcaption').innerHTML = (stepPart >= 0 && M.parts[stepPart].sheet === sheetNo ? `<span class="new">part ${stepPart}</span> ` : '') +
      (state.selected >= 0 ? `<span class="sel">part ${state.selected}</span> ` : '') +
      (state.step > 0 ? '· grey: parts already placed' : '');
  }
  $('sheet').addEventListener('click', (e) => {
    const c = $('sheet'), r = c.getBoundingClientRect();
    const x = (e.clientX - r.left) * c.width / r.width, y = (e.clientY - r.top) * c.height / r.height;
    const g = c.getContext('2d');
    for (const [part, path] of sheetPaths) if (g.isPointInPath(path, x, y)) { select(part); return; }
  });

  // ---- controls ----
  $('first').onclick = () => go(0);
  $('prev').onclick = () => go(state.step - 1);
  $('next').onclick = () => go(state.step + 1);
  $('last').onclick = () => go(steps.length);
  $('ghost').onchange = applyState;
  $('labels').onchange = applyState;
  $('find').onsubmit = (e) => {
    e.preventDefault();
    const text = $('search').value.trim();
    const q = /^\d+$/.test(text) ? Number(text) : -1;
    if (q >= 0 && q < n) select(q);
    else $('partinfo').innerHTML = `No part "${text.replace(/[<>&"]/g, '')}": parts are numbered 0 to ${n - 1}.`;
  };
  document.addEventListener('click', (e) => {
    const a = e.target.closest && e.target.closest('a.part');
    if (a) select(Number(a.dataset.part));
  });
  document.addEventListener('keydown', (e) => {
    if (e.target.tagName === 'INPUT') return;
    if (e.key === 'ArrowRight') go(state.step + 1);
    if (e.key === 'ArrowLeft') go(state.step - 1);
  });

  // For scripts and tests: the state and the number of part meshes drawn.
  window.kerfabGuide = { go, select, state, meshes: () => (three ? three.meshes.length : 0) };
  setUp3d();
  const hash = new URLSearchParams(location.hash.slice(1));
  const wanted = (key) => (/^\d+$/.test(hash.get(key) || '') ? Number(hash.get(key)) : -1);
  if (wanted('part') >= 0 && wanted('part') < n) select(wanted('part'));
  go(Math.max(0, wanted('step')));
  document.body.dataset.meshes = String(three ? three.meshes.length : 0);
  document.body.dataset.ready = '1';
})();
