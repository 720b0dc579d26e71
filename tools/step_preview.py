# STEP files as an independent CAD kernel reads them: gmsh's OpenCASCADE
# tessellates each file's faces, matplotlib draws them seen from below
# (where the light leaves), one colour per face.
#   pip install gmsh matplotlib
#   python3 tools/step_preview.py A.step [B.step ...] preview.png
import sys, gmsh, numpy as np
import matplotlib; matplotlib.use("Agg")
import matplotlib.pyplot as plt
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
files = sys.argv[1:-1]; out = sys.argv[-1]
fig = plt.figure(figsize=(5*len(files), 5.5))
for k, f in enumerate(files):
    gmsh.initialize(); gmsh.option.setNumber("General.Terminal", 0)
    gmsh.merge(f)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 24)
    gmsh.option.setNumber("Mesh.MeshSizeMax", 8)
    gmsh.model.mesh.generate(2)
    ax = fig.add_subplot(1, len(files), k+1, projection="3d")
    colours = plt.cm.tab10.colors
    tris_all = []
    for i, (d, t) in enumerate(gmsh.model.getEntities(2)):
        name = gmsh.model.getEntityName(d, t)
        types, _, nodes = gmsh.model.mesh.getElements(d, t)
        ntags, coords, _ = gmsh.model.mesh.getNodes(d, t, includeBoundary=True)
        pos = {int(n): coords[3*j:3*j+3] for j, n in enumerate(ntags)}
        for ty, nd in zip(types, nodes):
            if ty != 2: continue
            tri = [[pos[int(n)] for n in nd[3*j:3*j+3]] for j in range(len(nd)//3)]
            tris_all.extend(tri)
            ax.add_collection3d(Poly3DCollection(tri, facecolor=colours[i % 10], edgecolor=(0,0,0,0.15), linewidth=0.2, alpha=0.85))
    pts = np.array(tris_all).reshape(-1,3)
    lo, hi = pts.min(0), pts.max(0); c = (lo+hi)/2; r = (hi-lo).max()/2
    ax.set_xlim(c[0]-r, c[0]+r); ax.set_ylim(c[1]-r, c[1]+r); ax.set_zlim(c[2]-r, c[2]+r)
    ax.set_xlabel("x mm"); ax.set_ylabel("y mm"); ax.set_zlabel("z mm")
    ax.view_init(elev=-25, azim=-60)
    ax.set_title(f.split("/")[-1] + f"\n{len(gmsh.model.getEntities(2))} faces, {len(tris_all)} triangles (gmsh/OCC)", fontsize=9)
    gmsh.finalize()
plt.tight_layout(); plt.savefig(out, dpi=90)
