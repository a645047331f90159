package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertEquals
import kotlin.math.sqrt
import kotlin.random.Random

/** Seeded random test inputs and tolerance assertions shared by the property tests. */
object Randoms {
    /** A uniformly distributed unit quaternion (normalised 4-D Gaussian), w of either sign. */
    fun quaternion(rnd: Random): Quaternion {
        while (true) {
            val q = Quaternion(gaussian(rnd), gaussian(rnd), gaussian(rnd), gaussian(rnd))
            if (q.norm() > 1e-3) return q.normalized()
        }
    }

    fun vector(rnd: Random, scale: Double = 1.0) =
        Vector3(rnd.nextDouble(-scale, scale), rnd.nextDouble(-scale, scale), rnd.nextDouble(-scale, scale))

    fun unitVector(rnd: Random): Vector3 {
        while (true) {
            val v = Vector3(gaussian(rnd), gaussian(rnd), gaussian(rnd))
            if (v.norm() > 1e-3) return v.normalized()
        }
    }

    private fun gaussian(rnd: Random): Double {
        // Box-Muller
        val u = rnd.nextDouble(1e-12, 1.0)
        val v = rnd.nextDouble()
        return sqrt(-2.0 * kotlin.math.ln(u)) * kotlin.math.cos(2.0 * Math.PI * v)
    }
}

fun assertClose(expected: Vector3, actual: Vector3, tolerance: Double, message: () -> String = { "" }) {
    assertEquals(0.0, (expected - actual).norm(), tolerance) { "expected $expected, got $actual. ${message()}" }
}

fun assertClose(expected: RotationMatrix, actual: RotationMatrix, tolerance: Double, message: () -> String = { "" }) {
    val e = expected.toDoubleArray()
    val a = actual.toDoubleArray()
    for (i in 0 until 9) assertEquals(e[i], a[i], tolerance) { "element $i: expected $expected, got $actual. ${message()}" }
}

/** Same rotation: q and −q are equal as rotations. */
fun assertSameRotation(expected: Quaternion, actual: Quaternion, tolerance: Double, message: () -> String = { "" }) {
    assertEquals(1.0, kotlin.math.abs(expected.dot(actual)), tolerance) { "expected ±$expected, got $actual. ${message()}" }
}
