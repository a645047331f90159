package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.Random
import kotlin.math.cos
import kotlin.math.sin

class InitialOrientationTest {
    private val random = Random(7)
    private fun randomOrientation() = Quaternion(random.nextGaussian(), random.nextGaussian(), random.nextGaussian(), random.nextGaussian()).normalized()

    @Test
    fun `recovers any orientation from gravity and a dipping field (NWU)`() {
        val up = Vector3(0.0, 0.0, 9.81)
        repeat(10_000) {
            val q = randomOrientation()
            val dip = (random.nextDouble() * 2.0 - 1.0) * 1.4
            val field = Vector3(45.0 * cos(dip), 0.0, -45.0 * sin(dip)) // NWU: north horizontal, down with positive dip
            val a = q.inverseRotate(up)
            val m = q.inverseRotate(field)
            val est = InitialOrientation.nwu(a.x, a.y, a.z, true, m.x, m.y, m.z)
            assertTrue(est.angleTo(q) < 1e-9, "error ${est.angleTo(q)} for $q")
        }
    }

    @Test
    fun `without a magnetometer matches inclination, including upside down`() {
        val accs = List(10_000) { randomOrientation().inverseRotate(Vector3.UNIT_Z) } + Vector3(0.0, 0.0, -1.0) + Vector3(1e-9, 0.0, -1.0)
        for (a in accs) {
            val est = InitialOrientation.nwu(a.x, a.y, a.z, false, 0.0, 0.0, 0.0)
            assertTrue((est.rotate(a.normalized()) - Vector3.UNIT_Z).norm() < 1e-8, "up maps to ${est.rotate(a)} for $a")
            assertTrue(est.isFinite())
        }
    }

    @Test
    fun `a field parallel to gravity falls back to inclination only`() {
        val est = InitialOrientation.nwu(0.0, 0.0, 9.81, true, 0.0, 0.0, -40.0)
        assertTrue(est.angleTo(Quaternion.IDENTITY) < 1e-12)
    }
}
