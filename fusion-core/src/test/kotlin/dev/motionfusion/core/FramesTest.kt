package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import kotlin.math.sqrt
import kotlin.random.Random

class FramesTest {

    private val rnd = Random(21)
    private val east = Vector3(1.0, 0.0, 0.0) // in ENU
    private val north = Vector3(0.0, 1.0, 0.0)
    private val up = Vector3(0.0, 0.0, 1.0)

    @Test
    fun `directions land on the axes each frame defines`() {
        // NWU: x north, y west, z up.
        assertEquals(Vector3(1.0, 0.0, 0.0), convertVector(north, WorldFrame.ENU, WorldFrame.NWU))
        assertEquals(Vector3(0.0, -1.0, 0.0), convertVector(east, WorldFrame.ENU, WorldFrame.NWU))
        assertEquals(Vector3(0.0, 0.0, 1.0), convertVector(up, WorldFrame.ENU, WorldFrame.NWU))
        // NED: x north, y east, z down.
        assertEquals(Vector3(1.0, 0.0, 0.0), convertVector(north, WorldFrame.ENU, WorldFrame.NED))
        assertEquals(Vector3(0.0, 1.0, 0.0), convertVector(east, WorldFrame.ENU, WorldFrame.NED))
        assertEquals(Vector3(0.0, 0.0, -1.0), convertVector(up, WorldFrame.ENU, WorldFrame.NED))
    }

    @Test
    fun `q_ENU = cos45 0 0 sin45 times q_NWU, and the NED quaternion of CONVENTIONS md`() {
        val h = sqrt(0.5)
        assertSameRotation(Quaternion(h, 0.0, 0.0, h), WorldFrame.NWU.quaternionTo(WorldFrame.ENU), 1e-15)
        assertSameRotation(Quaternion(0.0, h, h, 0.0), WorldFrame.NED.quaternionTo(WorldFrame.ENU), 1e-15)
        repeat(1_000) {
            val qNwu = Randoms.quaternion(rnd)
            assertSameRotation(Quaternion(h, 0.0, 0.0, h) * qNwu, convertOrientation(qNwu, WorldFrame.NWU, WorldFrame.ENU), 1e-15)
        }
    }

    @Test
    fun `conversions invert, compose, and agree between vectors, quaternions and matrices`() {
        val frames = WorldFrame.entries
        repeat(10_000) {
            val a = frames[rnd.nextInt(3)]
            val b = frames[rnd.nextInt(3)]
            val c = frames[rnd.nextInt(3)]
            val q = Randoms.quaternion(rnd)
            val v = Randoms.vector(rnd, 50.0)
            assertEquals(v, convertVector(convertVector(v, a, b), b, a)) // exact: signed permutations
            assertSameRotation(q, convertOrientation(convertOrientation(q, a, b), b, a), 1e-15)
            assertSameRotation(convertOrientation(q, a, c), convertOrientation(convertOrientation(q, a, b), b, c), 1e-15)
            // A sensor vector mapped to frame a then converted equals mapping with the converted orientation.
            val s = Randoms.vector(rnd, 10.0)
            assertClose(convertVector(q.rotate(s), a, b), convertOrientation(q, a, b).rotate(s), 1e-13)
            assertClose(convertOrientation(q.toRotationMatrix(), a, b), convertOrientation(q, a, b).toRotationMatrix(), 1e-15)
            assertClose(a.rotationTo(b), a.quaternionTo(b).toRotationMatrix(), 1e-15)
        }
    }
}
