// report.html's 3D view (io/report_page/report_page.h): the mesh, the slices as translucent
// planes and their contours, from the JSON block #view-data (typed arrays in base64, little
// endian), drawn with three.js (THREE, THREE.OrbitControls inlined before this script).
(function () {
  'use strict';
  var body = document.body;
  var note = document.getElementById('view-note');
  var canvas = document.getElementById('view-canvas');
  var data = JSON.parse(document.getElementById('view-data').textContent);

  function bytes(b64) {
    var s = atob(b64), n = s.length, out = new Uint8Array(n);
    for (var i = 0; i < n; ++i) out[i] = s.charCodeAt(i);
    return out.buffer;
  }
  function floats(b64) { return b64 ? new Float32Array(bytes(b64)) : new Float32Array(0); }
  function uints(b64) { return b64 ? new Uint32Array(bytes(b64)) : new Uint32Array(0); }
  function shorts(b64) { return b64 ? new Uint16Array(bytes(b64)) : new Uint16Array(0); }
  function octets(b64) { return b64 ? new Uint8Array(bytes(b64)) : new Uint8Array(0); }

  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    note.textContent = 'This browser cannot draw WebGL; the 3D view is not available (' + e.message + ').';
    return;
  }
  var background = data.background || '#f4f5f7';
  renderer.setClearColor(new THREE.Color(background), 1);
  renderer.setPixelRatio(1);

  var scene = new THREE.Scene();
  var lo = data.bounds[0], hi = data.bounds[1];
  var centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  var radius = Math.max(1e-9, 0.5 * Math.sqrt(Math.pow(hi[0] - lo[0], 2) + Math.pow(hi[1] - lo[1], 2) + Math.pow(hi[2] - lo[2], 2)));
  var camera = new THREE.PerspectiveCamera(35, 2, radius / 100, radius * 100);
  camera.up.set(0, 0, 1);
  // The direction the object is first seen from (from the front right, above).
  var viewDirection = new THREE.Vector3(1.9, -2.6, 1.2).normalize();
  camera.position.copy(centre).addScaledVector(viewDirection, 2.5 * radius);
  camera.lookAt(centre);
  scene.add(new THREE.AmbientLight(0xffffff, 0.45));
  var light = new THREE.DirectionalLight(0xffffff, 0.75);
  camera.add(light);
  light.position.set(0.3, 0.6, 1);
  scene.add(camera);

  // Material colours (label -> colour), the same palette as the frames' overlays.
  var palette = ['#4e79a7', '#f28e2b', '#59a14f', '#e15759', '#76b7b2', '#edc948', '#b07aa1', '#ff9da7', '#9c755f', '#bab0ac'];
  function labelColour(label) { return new THREE.Color(label < 1 ? '#a4abb6' : palette[(label - 1) % palette.length]); }

  // The mesh, coloured uniformly, by the sampling verdict of its cell, or by material.
  var mesh = null, meshColours = null, m = data.mesh;
  var positions = floats(m.positions), indices = uints(m.indices);
  // verdict per vertex: 0 satisfied, 1 violated, 2 undetermined (the cell's, report.json sampling.cells)
  var verdicts = octets(m.verdict), labels = shorts(m.label);
  if (indices.length > 0) {
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    geometry.setIndex(new THREE.BufferAttribute(indices, 1));
    geometry.computeVertexNormals();
    meshColours = new Float32Array(positions.length);
    geometry.setAttribute('color', new THREE.BufferAttribute(meshColours, 3));
    mesh = new THREE.Mesh(geometry, new THREE.MeshPhongMaterial({
      vertexColors: THREE.VertexColors, side: THREE.DoubleSide, shininess: 25,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1 }));
    scene.add(mesh);
  }
  var legend = document.getElementById('view-legend');
  function swatch(colour, text) {
    return '<span class="legend-swatch" style="background:' + colour + '"></span>' + text;
  }
  function colourMesh(mode) {
    if (!mesh) return;
    var c = new THREE.Color(), n = positions.length / 3;
    var pass = new THREE.Color('#3aa35b'), fail = new THREE.Color('#d64545'), unknown = new THREE.Color('#a4abb6');
    var uniform = new THREE.Color('#c9cfd8');
    for (var i = 0; i < n; ++i) {
      if (mode === 'sampling') {
        var v = verdicts.length ? verdicts[i] : 2;
        c.copy(v === 0 ? pass : (v === 1 ? fail : unknown));
      } else if (mode === 'material') {
        c.copy(labelColour(labels.length ? labels[i] : 1));
      } else c.copy(uniform);
      meshColours[3 * i] = c.r; meshColours[3 * i + 1] = c.g; meshColours[3 * i + 2] = c.b;
    }
    mesh.geometry.attributes.color.needsUpdate = true;
    if (mode === 'sampling')
      legend.innerHTML = swatch('#3aa35b', 'cell satisfies the sampling conditions') + swatch('#d64545', 'cell violates them') +
                         swatch('#a4abb6', 'undetermined');
    else if (mode === 'material')
      legend.innerHTML = (data.materials || [1]).map(function (l) { return swatch('#' + labelColour(l).getHexString(), 'label ' + l); }).join('') +
                         swatch('#a4abb6', 'no label');
    else legend.innerHTML = '';
  }

  // The slices: light translucent observed rectangles with outlines (flagged ones orange), and the
  // sections' contours on them. A few slices by default (an even choice of 8, and every flagged
  // one) with their contours, so that the mesh stays in sight; all of them on demand; with none,
  // the contours of every slice on the mesh alone.
  var fewSlices = new THREE.Group(), allSlices = new THREE.Group(), fewContours = new THREE.Group(),
      allContours = new THREE.Group(), contours = new THREE.Group();
  contours.add(fewContours);
  contours.add(allContours);
  var quads = floats(data.slices.quads), flagged = {};
  (data.slices.flagged || []).forEach(function (q) { flagged[q] = true; });
  var planeQuads = data.slices.plane_quads || [], planeSegments = data.contours.plane_segments || [];
  var nQuads = quads.length / 12, nPlanes = planeQuads.length;
  function sliceGroup(chosen) {
    var group = new THREE.Group(), n = chosen.length;
    if (n === 0) return group;
    var triangles = new Float32Array(n * 18), colours = new Float32Array(n * 18), edges = new Float32Array(n * 24);
    var normal = new THREE.Color('#8fa3c7'), warn = new THREE.Color('#f59e0b');
    var order = [0, 1, 2, 0, 2, 3], ring = [0, 1, 1, 2, 2, 3, 3, 0];
    chosen.forEach(function (q, k) {
      var col = flagged[q] ? warn : normal;
      for (var t = 0; t < 6; ++t)
        for (var a = 0; a < 3; ++a) {
          triangles[18 * k + 3 * t + a] = quads[12 * q + 3 * order[t] + a];
          colours[18 * k + 3 * t + a] = a === 0 ? col.r : (a === 1 ? col.g : col.b);
        }
      for (var e = 0; e < 8; ++e)
        for (var b = 0; b < 3; ++b) edges[24 * k + 3 * e + b] = quads[12 * q + 3 * ring[e] + b];
    });
    var planeGeometry = new THREE.BufferGeometry();
    planeGeometry.setAttribute('position', new THREE.BufferAttribute(triangles, 3));
    planeGeometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
    group.add(new THREE.Mesh(planeGeometry, new THREE.MeshBasicMaterial({
      vertexColors: THREE.VertexColors, transparent: true, opacity: Math.max(0.015, Math.min(0.06, 0.5 / n)),
      side: THREE.DoubleSide, depthWrite: false })));
    var edgeGeometry = new THREE.BufferGeometry();
    edgeGeometry.setAttribute('position', new THREE.BufferAttribute(edges, 3));
    group.add(new THREE.LineSegments(edgeGeometry, new THREE.LineBasicMaterial({
      color: 0x8fa3c7, transparent: true, opacity: Math.max(0.06, Math.min(0.35, 4 / n)) })));
    return group;
  }
  // The planes shown by default: an even choice of 8 and every flagged one, in the planes' order.
  var fewPlanes = {}, fewCount = Math.min(nPlanes, 8);
  for (var f = 0; f < fewCount; ++f) fewPlanes[Math.floor((f + 0.5) * nPlanes / fewCount)] = true;
  for (var p0 = 0; p0 < nPlanes; ++p0)
    if (planeQuads[p0] >= 0 && flagged[planeQuads[p0]]) fewPlanes[p0] = true;
  var every = [], few = [];
  for (var q = 0; q < nQuads; ++q) every.push(q);
  for (var p1 = 0; p1 < nPlanes; ++p1)
    if (fewPlanes[p1] && planeQuads[p1] >= 0) few.push(planeQuads[p1]);
  fewSlices.add(sliceGroup(few));
  allSlices.add(sliceGroup(every));
  allSlices.visible = false;

  // The contours, coloured by material, darker than the mesh: every plane's, and the few planes'.
  var segments = floats(data.contours.segments), segmentLabels = shorts(data.contours.labels);
  function contourLines(keep) {
    var n = 0, s = 0, start = [];
    for (var p2 = 0; p2 < nPlanes; ++p2) { start.push(s); s += planeSegments[p2]; if (keep(p2)) n += planeSegments[p2]; }
    if (nPlanes === 0) n = segments.length / 6;  // no per-plane counts: everything
    var pos = new Float32Array(6 * n), col = new Float32Array(6 * n), k = 0;
    function add(sIndex) {
      var lc = labelColour(segmentLabels.length ? segmentLabels[sIndex] : 1);
      lc.offsetHSL(0, 0, -0.18);
      for (var c = 0; c < 6; ++c) {
        pos[6 * k + c] = segments[6 * sIndex + c];
        col[6 * k + c] = c % 3 === 0 ? lc.r : (c % 3 === 1 ? lc.g : lc.b);
      }
      ++k;
    }
    if (nPlanes === 0) { for (var a = 0; a < n; ++a) add(a); }
    else
      for (var p3 = 0; p3 < nPlanes; ++p3)
        if (keep(p3)) for (var b = 0; b < planeSegments[p3]; ++b) add(start[p3] + b);
    var group = new THREE.Group();
    if (n === 0) return group;
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(col, 3));
    group.add(new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors })));
    return group;
  }
  allContours.add(contourLines(function () { return true; }));
  fewContours.add(contourLines(function (p) { return fewPlanes[p] === true; }));
  allContours.visible = false;
  scene.add(fewSlices);
  scene.add(allSlices);
  scene.add(contours);

  // The camera framed on the mesh (or, without one, on the slices): the nearest distance from which
  // every point of the mesh, seen from viewDirection in perspective, lies within 94% of the view.
  var framed = positions.length >= 3 ? positions : floats(data.slices.quads);
  function frame() {
    if (framed.length < 3) return;
    var w = Math.max(1, canvas.clientWidth), h = Math.max(1, canvas.clientHeight);
    var back = viewDirection;  // from the target towards the camera
    var right = new THREE.Vector3().crossVectors(back.clone().negate(), camera.up).normalize();
    var up = new THREE.Vector3().crossVectors(right, back.clone().negate()).normalize();
    var n = framed.length / 3, xs = new Float64Array(n), ys = new Float64Array(n), zs = new Float64Array(n);
    var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity], p = new THREE.Vector3();
    for (var i = 0; i < n; ++i) {
      p.set(framed[3 * i], framed[3 * i + 1], framed[3 * i + 2]);
      xs[i] = p.dot(right); ys[i] = p.dot(up); zs[i] = p.dot(back);
      var c = [xs[i], ys[i], zs[i]];
      for (var a = 0; a < 3; ++a) { lo[a] = Math.min(lo[a], c[a]); hi[a] = Math.max(hi[a], c[a]); }
    }
    var mx = (lo[0] + hi[0]) / 2, my = (lo[1] + hi[1]) / 2, mz = (lo[2] + hi[2]) / 2;
    var tanV = 0.94 * Math.tan(camera.fov * Math.PI / 360), tanH = tanV * w / h;
    var distance = 1e-9;
    for (var k = 0; k < n; ++k)
      distance = Math.max(distance, zs[k] - mz + Math.max(Math.abs(xs[k] - mx) / tanH, Math.abs(ys[k] - my) / tanV));
    var target = new THREE.Vector3().addScaledVector(right, mx).addScaledVector(up, my).addScaledVector(back, mz);
    var extent = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-6);
    camera.position.copy(target).addScaledVector(back, distance);
    camera.near = Math.max(distance / 1000, 1e-6);
    camera.far = distance + 100 * extent;
    camera.lookAt(target);
    centre.copy(target);
  }
  frame();

  var controls = new THREE.OrbitControls(camera, canvas);
  controls.target.copy(centre);
  controls.update();

  function resize() {
    var w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== w || canvas.height !== h) renderer.setSize(w, h, false);
    camera.aspect = w / Math.max(1, h);
    camera.updateProjectionMatrix();
  }
  function render() {
    resize();
    renderer.render(scene, camera);
  }
  controls.addEventListener('change', render);
  window.addEventListener('resize', render);

  var colourSelect = document.getElementById('view-colour');
  colourSelect.addEventListener('change', function () { colourMesh(colourSelect.value); render(); });
  function toggle(id, object) {
    var box = document.getElementById(id);
    box.addEventListener('change', function () { object.visible = box.checked; render(); });
  }
  var sliceSelect = document.getElementById('view-slices');
  function showSlices(which) {
    fewSlices.visible = fewContours.visible = which === 'few';
    allSlices.visible = which === 'all';
    allContours.visible = which !== 'few';
  }
  sliceSelect.addEventListener('change', function () { showSlices(sliceSelect.value); render(); });
  toggle('view-contours', contours);
  if (mesh) toggle('view-mesh', mesh);
  if (window.location.hash === '#mesh-only') {  // the mesh alone (tests/test_report_browser.cpp)
    sliceSelect.value = 'none';
    showSlices('none');
    document.getElementById('view-contours').checked = contours.visible = false;
  }

  colourMesh(colourSelect.value);
  render();
  var texts = [];
  if (m.triangles_shown < m.triangles)
    texts.push('mesh decimated for the browser: ' + m.triangles_shown + ' of ' + m.triangles + ' triangles');
  var fewShown = Object.keys(fewPlanes).length;
  if (fewShown < nPlanes)
    texts.push('slices: ' + fewShown + ' of ' + data.slices.total + ' shown with their contours (choose "all" to see ' +
               (data.slices.shown < data.slices.total ? data.slices.shown + ', an even choice' : 'every one') +
               ', "none" for every contour on the mesh alone)');
  texts.push('drag to turn, scroll to zoom, right-drag to pan');
  note.textContent = texts.join('; ') + '.';

  var rect = canvas.getBoundingClientRect();
  body.setAttribute('data-canvas-rect', [rect.left + window.scrollX, rect.top + window.scrollY, rect.width, rect.height]
                                            .map(function (v) { return String(Math.round(v)); }).join(' '));
  body.setAttribute('data-background', '#' + new THREE.Color(background).getHexString());
  body.setAttribute('data-view-ready', '1');
})();
