package dev.motionfusion.app.ui

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.RotationArrays
import kotlin.math.PI
import kotlin.math.cos
import kotlin.math.max
import kotlin.math.sin
import kotlin.math.sqrt

/**
 * A phone-shaped mesh and its projection for [PhoneModelView]; pure Kotlin, tested on the JVM.
 *
 * Frames (docs/CONVENTIONS.md): the mesh is built in the Android device frame (x right, y up
 * along the long edge, z out of the screen), in units of half the phone's length. An
 * orientation q maps device → ENU (v_world = q ⊗ v ⊗ q*), as the fused orientation and the
 * rotation vector do. The camera stands south of the phone and above it, looking north and
 * down by [ELEVATION_RAD]: a phone flat on a table with its top towards north shows its screen
 * from above, its top edge away from the viewer. Screen coordinates: x right, y down, in units
 * of the model's half length (the view scales them to pixels).
 *
 * Faces are convex polygons; [project] culls those facing away from the camera, shades the rest
 * with a fixed directional light (ambient + Lambert) and orders them back to front (painter's
 * algorithm). The body is one convex box, so its visible faces never overlap; everything else
 * (screen, camera bump, lenses) stands on one of its faces and is drawn right after that face,
 * when that face is seen: the bump, inset from the back's edges, is hidden by the body whenever
 * the back is. Nothing is allocated per call.
 */
internal class PhoneMesh {
    /** What a face is, for its colour. */
    enum class Part { BODY_FRONT, BODY_BACK, BODY_SIDE, SCREEN, FRONT_CAMERA, BUMP, BUMP_SIDE, LENS }

    private val faceCount: Int
    private val parts: Array<Part>
    /** Vertices per face (4 for boxes, [LENS_SIDES] for a lens), and the device-frame coordinates. */
    private val sides: IntArray
    private val model: Array<FloatArray>
    /** The face a part stands on (screen, bump, lens): drawn right after it; -1 for the body's faces. */
    private val parent: IntArray

    // Per projection: screen coordinates, depth, brightness, visibility and the drawing order.
    val screenX: Array<FloatArray>
    val screenY: Array<FloatArray>
    private val depth = FloatArray(MAX_FACES)
    val shade = FloatArray(MAX_FACES)
    private val visible = BooleanArray(MAX_FACES)
    /** Faces to draw, back to front: the first [drawCount] entries. */
    val order = IntArray(MAX_FACES)
    var drawCount = 0
        private set

    init {
        val b = Builder()
        // Body: 71 × 147 × 8 mm, scaled to a half length of 1.
        b.box(HX, HY, HZ, 0f, 0f, 0f, Part.BODY_FRONT, Part.BODY_BACK, Part.BODY_SIDE)
        val front = b.faceOf(Part.BODY_FRONT)
        // The screen on the front face, inset from the edges, slightly above it.
        b.face(Part.SCREEN, front, floatArrayOf(-HX + 0.04f, -HY + 0.05f, HZ, HX - 0.04f, -HY + 0.05f, HZ, HX - 0.04f, HY - 0.05f, HZ, -HX + 0.04f, HY - 0.05f, HZ))
        // The front camera's hole near the screen's top edge: which end is the top.
        b.face(Part.FRONT_CAMERA, b.faceOf(Part.SCREEN), circle(0f, HY - 0.13f, HZ, 0.035f, towardsPlusZ = true))
        // Camera bump on the back, top left as seen from the back (device +x, +y).
        val bx = 0.22f; val by = 0.72f; val bw = 0.17f; val bh = 0.19f; val bd = 0.035f
        b.box(bw, bh, bd / 2, bx, by, -HZ - bd / 2, Part.BUMP_SIDE, Part.BUMP, Part.BUMP_SIDE, parent = b.faceOf(Part.BODY_BACK), skipFront = true)
        val bump = b.faceOf(Part.BUMP)
        for ((lx, ly) in listOf(bx - 0.05f to by + 0.07f, bx - 0.05f to by - 0.08f, bx + 0.08f to by)) {
            b.face(Part.LENS, bump, circle(lx, ly, -HZ - bd, 0.055f, towardsPlusZ = false))
        }
        faceCount = b.parts.size
        parts = b.parts.toTypedArray()
        sides = b.sides.toIntArray()
        model = b.vertices.toTypedArray()
        parent = b.parents.toIntArray()
        screenX = Array(faceCount) { FloatArray(sides[it]) }
        screenY = Array(faceCount) { FloatArray(sides[it]) }
    }

    /** A disc of radius [r] about (x, y, z) in a plane of constant z, facing +z or −z. */
    private fun circle(x: Float, y: Float, z: Float, r: Float, towardsPlusZ: Boolean): FloatArray {
        val v = FloatArray(LENS_SIDES * 3)
        for (k in 0 until LENS_SIDES) {
            // Counter-clockwise as seen from the side it faces.
            val a = (if (towardsPlusZ) 2.0 else -2.0) * PI * k / LENS_SIDES
            v[3 * k] = x + r * cos(a).toFloat()
            v[3 * k + 1] = y + r * sin(a).toFloat()
            v[3 * k + 2] = z
        }
        return v
    }

    fun part(face: Int): Part = parts[face]
    fun sides(face: Int): Int = sides[face]

    /** The device-frame outward normal of [face]. */
    fun normal(face: Int, out: FloatArray) {
        val v = model[face]
        // Newell's method on the first three vertices (faces are planar).
        val ax = v[3] - v[0]; val ay = v[4] - v[1]; val az = v[5] - v[2]
        val bx = v[6] - v[0]; val by = v[7] - v[1]; val bz = v[8] - v[2]
        var nx = ay * bz - az * by
        var ny = az * bx - ax * bz
        var nz = ax * by - ay * bx
        val n = sqrt(nx * nx + ny * ny + nz * nz)
        nx /= n; ny /= n; nz /= n
        out[0] = nx; out[1] = ny; out[2] = nz
    }

    private val r = FloatArray(9)
    private val qa = DoubleArray(4)
    private val n = FloatArray(3)

    /**
     * Projects the mesh turned by [q] (device → ENU). Fills [screenX]/[screenY], [shade] and
     * [order] (the first [drawCount] faces, back to front).
     */
    fun project(q: Quaternion) {
        qa[0] = q.w; qa[1] = q.x; qa[2] = q.y; qa[3] = q.z
        RotationArrays.quaternionToRotationMatrix(qa, r)
        var count = 0
        for (f in 0 until faceCount) {
            normal(f, n)
            val wx = r[0] * n[0] + r[1] * n[1] + r[2] * n[2]
            val wy = r[3] * n[0] + r[4] * n[1] + r[5] * n[2]
            val wz = r[6] * n[0] + r[7] * n[1] + r[8] * n[2]
            // Facing the camera when the normal points against the view direction.
            val towards = -(wx * FX + wy * FY + wz * FZ)
            visible[f] = towards > 1e-4f
            shade[f] = AMBIENT + (1f - AMBIENT) * max(0f, wx * LX + wy * LY + wz * LZ)
            val v = model[f]
            var d = 0f
            for (k in 0 until sides[f]) {
                val px = v[3 * k]; val py = v[3 * k + 1]; val pz = v[3 * k + 2]
                val ex = r[0] * px + r[1] * py + r[2] * pz
                val ey = r[3] * px + r[4] * py + r[5] * pz
                val ez = r[6] * px + r[7] * py + r[8] * pz
                val depthK = ex * FX + ey * FY + ez * FZ
                val s = CAMERA_DISTANCE / (CAMERA_DISTANCE + depthK)
                screenX[f][k] = ex * s
                screenY[f][k] = -(ex * UX + ey * UY + ez * UZ) * s
                d += depthK
            }
            depth[f] = d / sides[f]
            if (visible[f] && parent[f] < 0) order[count++] = f
        }
        // Back to front: the farthest face first (insertion sort: at most a dozen faces).
        for (i in 1 until count) {
            val f = order[i]
            var j = i - 1
            while (j >= 0 && depth[order[j]] < depth[f]) { order[j + 1] = order[j]; j-- }
            order[j + 1] = f
        }
        // What stands on a face right after it, when both are seen (and what stands on that next).
        var total = count
        var i = 0
        while (i < total) {
            val f = order[i]
            var at = i + 1
            for (g in 0 until faceCount) {
                if (parent[g] == f && visible[g]) {
                    System.arraycopy(order, at, order, at + 1, total - at)
                    order[at++] = g
                    total++
                }
            }
            i++
        }
        drawCount = total
    }

    private class Builder {
        val parts = ArrayList<Part>()
        val sides = ArrayList<Int>()
        val vertices = ArrayList<FloatArray>()
        val parents = ArrayList<Int>()

        fun faceOf(p: Part): Int = parts.lastIndexOf(p)

        fun face(p: Part, parent: Int, v: FloatArray) {
            parts += p; sides += v.size / 3; vertices += v; parents += parent
        }

        /** A box of half sizes (hx, hy, hz) about (cx, cy, cz); quads counter-clockwise seen from outside. */
        fun box(
            hx: Float, hy: Float, hz: Float, cx: Float, cy: Float, cz: Float,
            front: Part, back: Part, side: Part, parent: Int = -1, skipFront: Boolean = false,
        ) {
            val x0 = cx - hx; val x1 = cx + hx; val y0 = cy - hy; val y1 = cy + hy; val z0 = cz - hz; val z1 = cz + hz
            if (!skipFront) face(front, parent, floatArrayOf(x0, y0, z1, x1, y0, z1, x1, y1, z1, x0, y1, z1))
            face(back, parent, floatArrayOf(x0, y0, z0, x0, y1, z0, x1, y1, z0, x1, y0, z0))
            face(side, parent, floatArrayOf(x1, y0, z0, x1, y1, z0, x1, y1, z1, x1, y0, z1)) // right (+x)
            face(side, parent, floatArrayOf(x0, y0, z0, x0, y0, z1, x0, y1, z1, x0, y1, z0)) // left (−x)
            face(side, parent, floatArrayOf(x0, y1, z0, x0, y1, z1, x1, y1, z1, x1, y1, z0)) // top (+y)
            face(side, parent, floatArrayOf(x0, y0, z0, x1, y0, z0, x1, y0, z1, x0, y0, z1)) // bottom (−y)
        }
    }

    companion object {
        const val HX = 0.483f
        const val HY = 1f
        const val HZ = 0.054f
        const val LENS_SIDES = 14
        private const val MAX_FACES = 32

        /** The camera looks north and down by this angle. */
        val ELEVATION_RAD = Math.toRadians(35.0)

        /** Distance from the camera to the phone's centre, in half lengths: a mild perspective. */
        const val CAMERA_DISTANCE = 6f

        /** View direction (camera → phone) in ENU, and the camera's up. */
        private val FX = 0f
        private val FY = cos(ELEVATION_RAD).toFloat()
        private val FZ = -sin(ELEVATION_RAD).toFloat()
        private val UX = 0f
        private val UY = sin(ELEVATION_RAD).toFloat()
        private val UZ = cos(ELEVATION_RAD).toFloat()

        /** Towards the light, ENU: from above, over the viewer's left shoulder. */
        private val LX: Float
        private val LY: Float
        private val LZ: Float
        private const val AMBIENT = 0.38f

        init {
            val lx = -0.45; val ly = -0.55; val lz = 1.0
            val n = sqrt(lx * lx + ly * ly + lz * lz)
            LX = (lx / n).toFloat(); LY = (ly / n).toFloat(); LZ = (lz / n).toFloat()
        }

        /** Projects the ENU point ([e], [nn], [u]) as [project] does the mesh, into [out] (x, y): for the earth frame. */
        fun toScreen(e: Float, nn: Float, u: Float, out: FloatArray) {
            val d = e * FX + nn * FY + u * FZ
            val s = CAMERA_DISTANCE / (CAMERA_DISTANCE + d)
            out[0] = e * s
            out[1] = -(e * UX + nn * UY + u * UZ) * s
        }
    }
}
