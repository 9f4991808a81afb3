// The three.js side of the viewer: one position buffer for every vertex of
// the stream (level l is a prefix of it, so coarser levels reuse the finer
// ones' buffer), one colour buffer, and what is drawn of the shown level:
// triangles over those buffers (its surface, or the kept side of a cut),
// shrunken cells, and optional edges. Renders on demand, not every frame.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export class LevelScene {
  // onRendered(): called after each frame is drawn.
  constructor(canvas, onRendered) {
    this.renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0xffffff, 1);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(30, 1, 0.01, 1000);
    const key = new THREE.DirectionalLight(0xffffff, 2.8);
    key.position.set(0.5, 0.8, 1);
    this.camera.add(key);  // the light follows the eye
    this.scene.add(this.camera);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x303030, 0.8));
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.addEventListener('change', () => this.requestRender());
    this.onRendered = onRendered;
    this.pending = false;

    this.material = new THREE.MeshStandardMaterial({
      vertexColors: true, flatShading: true, side: THREE.DoubleSide, roughness: 0.85, metalness: 0,
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    this.edgeMaterial = new THREE.LineBasicMaterial({ color: 0x303030, transparent: true, opacity: 0.45 });
    this.mesh = null;
    this.edges = null;
    this.cells = null;
    this.framed = false;

    new ResizeObserver(() => this.#resize()).observe(canvas);
    this.#resize();
    this.#compileShaders();
  }

  // Room for every vertex of the stream.
  allocate(vertexCount) {
    this.position = new THREE.BufferAttribute(new Float32Array(3 * vertexCount), 3);
    this.colour = new THREE.BufferAttribute(new Float32Array(3 * vertexCount), 3);
  }

  get colours() { return this.colour.array; }
  get positions() { return this.position.array; }

  // The positions of vertices [first, first + floats.length / 3).
  addPositions(first, floats) {
    this.position.array.set(floats, 3 * first);
    this.position.addUpdateRange(3 * first, floats.length);
    this.position.needsUpdate = true;
  }

  coloursChanged(count) {
    this.colour.addUpdateRange(0, 3 * count);
    this.colour.needsUpdate = true;
    this.requestRender();
  }

  // Draws these triangles (indices into the shared buffers), and their
  // edges if given.
  showTriangles(triangles, edges) {
    this.#clear();
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', this.position);
    geometry.setAttribute('color', this.colour);
    geometry.setIndex(new THREE.BufferAttribute(triangles, 1));
    this.mesh = new THREE.Mesh(geometry, this.material);
    this.scene.add(this.mesh);
    this.#showEdges(edges);
    this.requestRender();
  }

  // Draws non-indexed triangles with their own positions and colours
  // (shrunken cells, triangles coloured by their cell's region), and edges:
  // indices into the triangles' own positions, or with `sharedEdges` into
  // the shared buffer.
  showSoup({ position, colour }, edges, sharedEdges = false) {
    this.#clear();
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(position, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(colour, 3));
    this.mesh = new THREE.Mesh(geometry, this.material);
    this.scene.add(this.mesh);
    if (edges && sharedEdges) {
      this.#showEdges(edges);
    } else if (edges) {
      const lines = new THREE.BufferGeometry();
      lines.setAttribute('position', geometry.getAttribute('position'));
      lines.setIndex(new THREE.BufferAttribute(edges, 1));
      this.edges = new THREE.LineSegments(lines, this.edgeMaterial);
      this.scene.add(this.edges);
    }
    this.requestRender();
  }

  // Points the camera at the box [min, max] from the direction given by
  // azimuth and elevation (degrees; 0, 0 looks down -z with y up).
  frame(min, max, azimuth = 0, elevation = 0) {
    const centre = new THREE.Vector3().addVectors(min, max).multiplyScalar(0.5);
    const radius = Math.max(1e-9, new THREE.Vector3().subVectors(max, min).length() / 2);
    const distance = (radius / Math.sin(THREE.MathUtils.degToRad(this.camera.fov / 2))) * 0.92;
    const a = THREE.MathUtils.degToRad(azimuth), e = THREE.MathUtils.degToRad(elevation);
    const direction = new THREE.Vector3(Math.sin(a) * Math.cos(e), Math.sin(e), Math.cos(a) * Math.cos(e));
    this.camera.position.copy(centre).addScaledVector(direction, distance);
    this.camera.near = distance / 100;
    this.camera.far = distance * 10;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.framed = true;
    this.requestRender();
  }

  requestRender() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.renderer.render(this.scene, this.camera);
      this.onRendered?.();
    });
  }

  #showEdges(edges) {
    if (!edges) return;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', this.position);
    geometry.setIndex(new THREE.BufferAttribute(edges, 1));
    this.edges = new THREE.LineSegments(geometry, this.edgeMaterial);
    this.scene.add(this.edges);
  }

  // Compiles the surface's shaders now, while the stream is arriving, rather
  // than when the first level is drawn (seconds on a software renderer).
  #compileShaders() {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(new Float32Array(9), 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(new Float32Array(9), 3));
    const mesh = new THREE.Mesh(geometry, this.material);
    this.scene.add(mesh);
    this.renderer.compile(this.scene, this.camera);
    this.scene.remove(mesh);
    geometry.dispose();
  }

  #clear() {
    for (const object of [this.mesh, this.edges]) {
      if (!object) continue;
      this.scene.remove(object);
      object.geometry.dispose();
    }
    this.mesh = this.edges = null;
  }

  #resize() {
    const canvas = this.renderer.domElement;
    const width = canvas.clientWidth || 1, height = canvas.clientHeight || 1;
    this.renderer.setSize(width, height, false);
    this.camera.aspect = width / height;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }
}
