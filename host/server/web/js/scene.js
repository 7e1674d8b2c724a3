// A vessel scene with three.js (Debian's libjs-three, served at /lib/three/): the case's surface
// as the server meshes it (GET .../mesh, "CBXMESH1" binary), the tools as lines, the tip, the
// wall contacts coloured by force, the target. Used by the live view and the debrief.
import * as THREE from '/lib/three/build/three.module.js';
import { OrbitControls } from '/lib/three/examples/jsm/controls/OrbitControls.js';
import { api } from './api.js';

const meshes = new Map();  // "case/version" -> Promise of the parsed mesh

// {positions: Float32Array, normals: Float32Array, indices: Uint32Array}
export function loadMesh(caseName, version) {
  const key = caseName + '/' + (version || 'latest');
  if (!meshes.has(key)) {
    meshes.set(key, api('/cases/' + encodeURIComponent(caseName) + '/versions/' + (version || 'latest') + '/mesh', { raw: true })
      .then(parseMesh));
  }
  return meshes.get(key);
}

export function parseMesh(buffer) {
  const magic = new TextDecoder().decode(new Uint8Array(buffer, 0, 8));
  if (magic !== 'CBXMESH1') throw new Error('mesh: not a CBXMESH1 file');
  const head = new DataView(buffer, 8, 8);
  const v = head.getUint32(0, true);
  const t = head.getUint32(4, true);
  return {
    positions: new Float32Array(buffer, 16, 3 * v),
    normals: new Float32Array(buffer, 16 + 12 * v, 3 * v),
    indices: new Uint32Array(buffer, 16 + 24 * v, 3 * t),
  };
}

// Wall force (mN) to a colour: green (light touch) through yellow to red (at `hot`).
export function forceColor(f, hot = 200) {
  const x = Math.max(0, Math.min(1, f / hot));
  return new THREE.Color().setHSL((1 - x) * 0.33, 1, 0.5);
}

// The WebGL implementation's name (WEBGL_debug_renderer_info where the browser offers it, else
// RENDERER) and whether it rasterises on the CPU (SwiftShader, Mesa's llvmpipe/softpipe, Windows'
// Basic Render Driver): there every frame drawn is CPU taken from everything else on the machine.
export function glRenderer(gl) {
  const info = gl.getExtension('WEBGL_debug_renderer_info');
  const name = String(gl.getParameter(info ? info.UNMASKED_RENDERER_WEBGL : gl.RENDERER));
  return { name, software: /swiftshader|llvmpipe|softpipe|software|basic render/i.test(name) };
}

const MAX_NODES = 256;
const MAX_CONTACTS = 32;

export class VesselView {
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setClearColor(0x101418);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(40, 1, 1, 5000);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x303040, 1.0));
    const sun = new THREE.DirectionalLight(0xffffff, 0.5);
    sun.position.set(1, 2, 3);
    this.scene.add(sun);
    this.tools = [];
    this.tip = new THREE.Mesh(new THREE.SphereBufferGeometry(1.2, 12, 8), new THREE.MeshBasicMaterial({ color: 0x40c0ff }));
    this.tip.visible = false;
    this.scene.add(this.tip);
    const cg = new THREE.BufferGeometry();
    cg.setAttribute('position', new THREE.BufferAttribute(new Float32Array(MAX_CONTACTS * 3), 3));
    cg.setAttribute('color', new THREE.BufferAttribute(new Float32Array(MAX_CONTACTS * 3), 3));
    cg.setDrawRange(0, 0);
    this.contacts = new THREE.Points(cg, new THREE.PointsMaterial({ size: 6, sizeAttenuation: false, vertexColors: THREE.VertexColors }));
    this.scene.add(this.contacts);
    this.resize();
    this.dirty = true;  // something changed since the last render
    this.controls.addEventListener('change', () => { this.dirty = true; });
    this.observer = new ResizeObserver(() => this.resize());
    this.observer.observe(container);
  }

  resize() {
    const w = Math.max(1, this.container.clientWidth);
    const h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  setVessel(mesh) {
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(mesh.positions, 3));
    g.setAttribute('normal', new THREE.BufferAttribute(mesh.normals, 3));
    g.setIndex(new THREE.BufferAttribute(mesh.indices, 1));
    g.computeBoundingSphere();
    const m = new THREE.MeshLambertMaterial({ color: 0xd05050, transparent: true, opacity: 0.35, side: THREE.DoubleSide, depthWrite: false });
    if (this.vessel) this.scene.remove(this.vessel);
    this.vessel = new THREE.Mesh(g, m);
    this.scene.add(this.vessel);
    const s = g.boundingSphere;
    this.controls.target.copy(s.center);
    this.camera.position.set(s.center.x + s.radius * 0.2, s.center.y - s.radius * 0.3, s.center.z + s.radius * 1.7);
    this.camera.near = s.radius / 100;
    this.camera.far = s.radius * 20;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.dirty = true;
  }

  setTarget(p, radius) {
    this.dirty = true;
    if (!p) return;
    const t = new THREE.Mesh(new THREE.SphereBufferGeometry(radius || 2, 16, 12),
      new THREE.MeshBasicMaterial({ color: 0x40ff80, wireframe: true }));
    t.position.set(p[0], p[1], p[2]);
    this.scene.add(t);
  }

  tool(i) {
    while (this.tools.length <= i) {
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(MAX_NODES * 3), 3));
      g.setDrawRange(0, 0);
      const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: this.tools.length === 0 ? 0xffffff : 0xffd040 }));
      line.frustumCulled = false;
      this.scene.add(line);
      this.tools.push(line);
    }
    return this.tools[i];
  }

  // Nodes as [[x,y,z],...] or a flat array.
  setTool(i, nodes) {
    this.dirty = true;
    const line = this.tool(i);
    const a = line.geometry.attributes.position;
    const flat = nodes.length && Array.isArray(nodes[0]) ? nodes.flat() : nodes;
    const n = Math.min(MAX_NODES, Math.floor(flat.length / 3));
    a.array.set(flat.length > n * 3 ? flat.slice(0, n * 3) : flat);
    a.needsUpdate = true;
    line.geometry.setDrawRange(0, n);
  }

  setTip(p) {
    this.dirty = true;
    if (!p) return;
    this.tip.visible = true;
    this.tip.position.set(p[0], p[1], p[2]);
  }

  // [{p_mm:[x,y,z], f_mN}]
  setContacts(list) {
    this.dirty = true;
    const g = this.contacts.geometry;
    const n = Math.min(MAX_CONTACTS, list ? list.length : 0);
    for (let i = 0; i < n; ++i) {
      g.attributes.position.array.set(list[i].p_mm, i * 3);
      const c = forceColor(list[i].f_mN);
      g.attributes.color.array.set([c.r, c.g, c.b], i * 3);
    }
    g.attributes.position.needsUpdate = true;
    g.attributes.color.needsUpdate = true;
    g.setDrawRange(0, n);
  }

  // A polyline that stays (the debrief's tip path).
  addPath(flat, color = 0x40c0ff) {
    this.dirty = true;
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(flat), 3));
    const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color, transparent: true, opacity: 0.6 }));
    this.scene.add(line);
    return line;
  }

  // Draws when something changed (a frame, the camera, the size); true if it drew.
  render(force = false) {
    this.controls.update();
    if (!this.dirty && !force) return false;
    this.renderer.render(this.scene, this.camera);
    this.dirty = false;
    return true;
  }

  dispose() {
    this.observer.disconnect();
    this.renderer.dispose();
    this.container.innerHTML = '';
  }
}
