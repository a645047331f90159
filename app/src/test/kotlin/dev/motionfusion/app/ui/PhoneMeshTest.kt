package dev.motionfusion.app.ui

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * The phone model's projection against docs/CONVENTIONS.md: orientations device → ENU, the
 * camera south of the phone looking north and down. Screen y grows downwards.
 */
class PhoneMeshTest {
    private val mesh = PhoneMesh()

    private fun drawn(): List<PhoneMesh.Part> = (0 until mesh.drawCount).map { mesh.part(mesh.order[it]) }

    private fun screenFace(): Int = (0 until mesh.drawCount).map { mesh.order[it] }.first { mesh.part(it) == PhoneMesh.Part.SCREEN }

    /** Mean screen position of the screen decal's bottom edge (vertices 0, 1) and top edge (2, 3). */
    private fun edges(f: Int): Pair<FloatArray, FloatArray> {
        val x = mesh.screenX[f]
        val y = mesh.screenY[f]
        return floatArrayOf((x[0] + x[1]) / 2, (y[0] + y[1]) / 2) to floatArrayOf((x[2] + x[3]) / 2, (y[2] + y[3]) / 2)
    }

    @Test
    fun `flat on a table with the top towards north, the screen is seen from above, its top edge away from the viewer`() {
        mesh.project(Quaternion.IDENTITY)
        val parts = drawn()
        assertTrue(PhoneMesh.Part.SCREEN in parts, parts.toString())
        assertFalse(PhoneMesh.Part.BODY_BACK in parts, parts.toString())
        assertFalse(PhoneMesh.Part.LENS in parts, "the camera is on the back: $parts")
        val (bottom, top) = edges(screenFace())
        assertTrue(top[1] < bottom[1], "top edge higher on screen: ${top[1]} vs ${bottom[1]}")
        assertEquals(0.0, top[0].toDouble(), 1e-5, "centred")
        // Perspective: the far (top) edge is narrower than the near one.
        val f = screenFace()
        assertTrue(mesh.screenX[f][2] - mesh.screenX[f][3] < mesh.screenX[f][1] - mesh.screenX[f][0])
        // The screen is drawn after the front face it lies on.
        assertTrue(parts.indexOf(PhoneMesh.Part.SCREEN) > parts.indexOf(PhoneMesh.Part.BODY_FRONT))
    }

    @Test
    fun `flat with the top towards east, the top edge points to the right`() {
        // Turned −90° about up: the device's y axis goes from north to east.
        val q = Quaternion.fromAxisAngle(Vector3.UNIT_Z, Math.toRadians(-90.0))
        assertEquals(1.0, q.rotate(Vector3(0.0, 1.0, 0.0)).x, 1e-12)
        mesh.project(q)
        val (bottom, top) = edges(screenFace())
        assertTrue(top[0] > bottom[0] + 1f, "top ${top[0]} right of bottom ${bottom[0]}")
    }

    @Test
    fun `screen down, the back, the camera bump and its lenses are seen, drawn after the back`() {
        mesh.project(Quaternion.fromAxisAngle(Vector3(0.0, 1.0, 0.0), Math.PI))
        val parts = drawn()
        assertFalse(PhoneMesh.Part.SCREEN in parts, parts.toString())
        val back = parts.indexOf(PhoneMesh.Part.BODY_BACK)
        val bump = parts.indexOf(PhoneMesh.Part.BUMP)
        assertTrue(back >= 0 && bump > back, parts.toString())
        assertEquals(3, parts.count { it == PhoneMesh.Part.LENS })
        assertTrue(parts.indexOfFirst { it == PhoneMesh.Part.LENS } > bump, parts.toString())
    }

    @Test
    fun `upright facing the viewer, the screen is seen, the top edge up`() {
        // Standing up, screen towards the south (the viewer): +90° about east turns the screen's normal from up to south.
        val q = Quaternion.fromAxisAngle(Vector3.UNIT_X, Math.toRadians(90.0))
        assertEquals(-1.0, q.rotate(Vector3.UNIT_Z).y, 1e-12)
        mesh.project(q)
        val (bottom, top) = edges(screenFace())
        assertTrue(top[1] < bottom[1] - 1f, "top ${top[1]} above bottom ${bottom[1]}")
        // The light comes from above and behind the viewer: the front face is lit beyond the ambient.
        val front = (0 until mesh.drawCount).map { mesh.order[it] }.first { mesh.part(it) == PhoneMesh.Part.BODY_FRONT }
        assertTrue(mesh.shade[front] > 0.38f)
    }
}
