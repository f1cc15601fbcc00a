// One 3D viewport. Several views share one camera and one orbit target, so
// they turn together: an input beside its remesh, seen the same way.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

const BACKGROUND = 0xf2f2f0;

export class View {
  constructor(container, camera, target, onChange) {
    this.container = container;
    this.camera = camera;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio);
    this.renderer.domElement.className = 'view-canvas';
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.scene.background = new THREE.Color(BACKGROUND);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x505060, 1.6));
    // A light at the camera, so the side one looks at is lit.
    this.light = new THREE.DirectionalLight(0xffffff, 1.8);
    this.scene.add(this.light);
    this.controls = new OrbitControls(camera, this.renderer.domElement);
    this.controls.target = target;
    this.controls.addEventListener('change', onChange);
    this.group = new THREE.Group();
    this.scene.add(this.group);
    this.item = null;
  }

  /** Shows an item ({geometry, colored}) or nothing; `wireframe` adds its edges. */
  show(item, wireframe) {
    for (const child of [...this.group.children]) {
      this.group.remove(child);
      if (child.userData.ownGeometry) child.geometry.dispose();
      child.material.dispose();
    }
    this.item = item;
    if (!item) return;
    const material = new THREE.MeshStandardMaterial({
      color: item.colored ? 0xffffff : 0xb9c6d8,
      vertexColors: !!item.colored,
      roughness: 0.75,
      metalness: 0.0,
      side: THREE.DoubleSide,
      polygonOffset: wireframe,
      polygonOffsetFactor: 1,
      polygonOffsetUnits: 1,
    });
    this.group.add(new THREE.Mesh(item.geometry, material));
    if (wireframe) {
      const edges = new THREE.LineSegments(
        new THREE.WireframeGeometry(item.geometry),
        new THREE.LineBasicMaterial({ color: 0x1d2a3a, transparent: true, opacity: 0.35 }),
      );
      edges.userData.ownGeometry = true;
      this.group.add(edges);
    }
  }

  /** Bounding sphere of what is shown, or null. */
  bounds() {
    if (!this.item) return null;
    this.item.geometry.computeBoundingSphere();
    return this.item.geometry.boundingSphere;
  }

  resize() {
    const { clientWidth: w, clientHeight: h } = this.container;
    if (w > 0 && h > 0) this.renderer.setSize(w, h, false);
  }

  render() {
    this.light.position.copy(this.camera.position);
    this.renderer.render(this.scene, this.camera);
  }
}
