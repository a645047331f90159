package dev.motionfusion.core.sensormanager

import android.hardware.SensorManager
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.random.Random

/**
 * Differential tests: every port in SensorManagerMath against the real AOSP
 * android.hardware.SensorManager of android-all 14, on seeded random inputs plus edges.
 * Floats are compared bit for bit with floatToIntBits: every bit of every non-NaN value, so −0
 * and +0 differ, while all NaNs count as one value. (NaN sign and payload are unspecified by the
 * JVM: on x86 a NaN result carries the sign of whichever NaN operand the interpreter or JIT put
 * first, so AOSP differs from itself: for gravity [9.518165, 8.980513, -9.932067] and
 * geomagnetic [Inf, Inf, NaN] its R[0] is 0xFFC00000 on the first calls and 0x7FC00000 once the
 * JIT has compiled it, after about 1,200 calls.) Outputs are pre-filled with the same
 * random garbage on both sides (so "untouched on failure" and "which elements are written" are
 * compared too), booleans and exceptions must match.
 */
class SensorManagerMathDifferentialTest {

    private val n = 20_000

    @Test
    fun `constants equal AOSP's`() {
        assertEquals(SensorManager.STANDARD_GRAVITY, SensorManagerMath.STANDARD_GRAVITY)
        assertEquals(SensorManager.GRAVITY_EARTH, SensorManagerMath.GRAVITY_EARTH)
        assertEquals(SensorManager.MAGNETIC_FIELD_EARTH_MAX, SensorManagerMath.MAGNETIC_FIELD_EARTH_MAX)
        assertEquals(SensorManager.MAGNETIC_FIELD_EARTH_MIN, SensorManagerMath.MAGNETIC_FIELD_EARTH_MIN)
        assertEquals(SensorManager.PRESSURE_STANDARD_ATMOSPHERE, SensorManagerMath.PRESSURE_STANDARD_ATMOSPHERE)
        assertEquals(SensorManager.AXIS_X, SensorManagerMath.AXIS_X)
        assertEquals(SensorManager.AXIS_Y, SensorManagerMath.AXIS_Y)
        assertEquals(SensorManager.AXIS_Z, SensorManagerMath.AXIS_Z)
        assertEquals(SensorManager.AXIS_MINUS_X, SensorManagerMath.AXIS_MINUS_X)
        assertEquals(SensorManager.AXIS_MINUS_Y, SensorManagerMath.AXIS_MINUS_Y)
        assertEquals(SensorManager.AXIS_MINUS_Z, SensorManagerMath.AXIS_MINUS_Z)
    }

    @Test
    fun `getRotationMatrix matches on random inputs, free fall and near-pole edges, all layouts`() {
        val rnd = Random(1)
        var successes = 0
        var freeFalls = 0
        var nearPole = 0
        repeat(n) {
            val gravity = when (it % 4) {
                0 -> vector(rnd, 12f) // includes small vectors: free fall
                1 -> direction(rnd, freeFallEdge(rnd)) // |g|² within a few ulps of 0.01·9.81²
                else -> direction(rnd, rnd.nextFloat() * 20f)
            }
            val geomagnetic = when (it % 5) {
                0 -> nearlyParallel(rnd, gravity) // |E × A| around 0.1
                1 -> special(rnd)
                else -> vector(rnd, 80f)
            }
            val ok = compareRotationMatrix(rnd, gravity, geomagnetic)
            val normSq = gravity[0] * gravity[0] + gravity[1] * gravity[1] + gravity[2] * gravity[2]
            when {
                ok -> successes++
                normSq < 0.01f * 9.81f * 9.81f -> freeFalls++
                else -> nearPole++ // |E × A| < 0.1
            }
        }
        println("getRotationMatrix: ok $successes, free fall $freeFalls, near pole $nearPole")
        // Every branch must have been exercised substantially.
        assertTrue(successes > n / 4 && freeFalls > n / 20 && nearPole > n / 50, "ok $successes, free fall $freeFalls, near pole $nearPole")
    }

    @Test
    fun `getRotationMatrix handles special values identically`() {
        val rnd = Random(2)
        repeat(2_000) { compareRotationMatrix(rnd, special(rnd), special(rnd)) }
        // Exactly zero field, exactly free fall, NaN gravity.
        compareRotationMatrix(rnd, floatArrayOf(0f, 0f, 9.81f), floatArrayOf(0f, 0f, 0f))
        compareRotationMatrix(rnd, floatArrayOf(0f, 0f, 0f), floatArrayOf(20f, 0f, -40f))
        compareRotationMatrix(rnd, floatArrayOf(Float.NaN, 0f, 9.81f), floatArrayOf(20f, 0f, -40f))
    }

    /** Runs both with every output layout (null, 9, 16, and an ignored length); returns AOSP's boolean. */
    private fun compareRotationMatrix(rnd: Random, gravity: FloatArray, geomagnetic: FloatArray): Boolean {
        val rLength = LAYOUTS[rnd.nextInt(LAYOUTS.size)]
        val iLength = LAYOUTS[rnd.nextInt(LAYOUTS.size)]
        val rA = rLength?.let { garbage(rnd, it) }
        val iA = iLength?.let { garbage(rnd, it) }
        val rB = rA?.copyOf()
        val iB = iA?.copyOf()
        val expected = SensorManager.getRotationMatrix(rA, iA, gravity, geomagnetic)
        val actual = SensorManagerMath.getRotationMatrix(rB, iB, gravity, geomagnetic)
        val ctx = { "gravity ${gravity.contentToString()} geomagnetic ${geomagnetic.contentToString()}" }
        assertEquals(expected, actual, ctx)
        assertBitsEqual(rA, rB, ctx)
        assertBitsEqual(iA, iB, ctx)
        return expected
    }

    @Test
    fun `getInclination matches on inclination matrices and random arrays of 9 and 16`() {
        val rnd = Random(3)
        repeat(n) {
            val i = if (it % 2 == 0) {
                FloatArray(if (rnd.nextBoolean()) 9 else 16).also {
                    SensorManager.getRotationMatrix(null, it, vector(rnd, 12f), vector(rnd, 60f))
                }
            } else {
                vectorOf(rnd, if (rnd.nextBoolean()) 9 else 16, 2f)
            }
            assertBitsEqual(SensorManager.getInclination(i), SensorManagerMath.getInclination(i)) { i.contentToString() }
        }
    }

    @Test
    fun `getOrientation matches on rotation matrices and arbitrary arrays, 9 and 16`() {
        val rnd = Random(4)
        repeat(n) {
            val length = if (rnd.nextBoolean()) 9 else 16
            val r = if (it % 2 == 0) rotationMatrix(rnd, length) else vectorOf(rnd, length, 1.2f) // |R7| > 1 → NaN
            val a = garbage(rnd, 3)
            val b = a.copyOf()
            val returnedA = SensorManager.getOrientation(r, a)
            val returnedB = SensorManagerMath.getOrientation(r, b)
            assertSame(a, returnedA)
            assertSame(b, returnedB)
            assertBitsEqual(a, b) { r.contentToString() }
        }
        // Lengths other than 9 are read as 16; too short throws the same exception.
        assertSameOutcome { m -> m.getOrientation(FloatArray(12), FloatArray(3)) }
        assertSameOutcome { m -> m.getOrientation(FloatArray(20) { 0.1f * it }, FloatArray(3)) }
    }

    @Test
    fun `remapCoordinateSystem matches for every axis pair, invalid axes, mismatched lengths and in == out`() {
        val rnd = Random(5)
        var accepted = 0
        repeat(n) {
            val x = axisArgument(rnd)
            val y = axisArgument(rnd)
            val inLength = if (rnd.nextBoolean()) 9 else 16
            val outLength = if (rnd.nextInt(10) == 0) 25 - inLength else inLength
            val inR = if (rnd.nextBoolean()) rotationMatrix(rnd, inLength) else vectorOf(rnd, inLength, 1f)
            val ctx = { "in ${inR.contentToString()} X $x Y $y out length $outLength" }
            if (rnd.nextInt(4) == 0) {
                // in == out (aliasing): AOSP goes through its static temp for 16, in place for 9.
                val a = inR.copyOf()
                val b = inR.copyOf()
                assertEquals(SensorManager.remapCoordinateSystem(a, x, y, a), SensorManagerMath.remapCoordinateSystem(b, x, y, b), ctx)
                assertBitsEqual(a, b, ctx)
            } else {
                val outA = garbage(rnd, outLength)
                val outB = outA.copyOf()
                val inCopy = inR.copyOf()
                val ok = SensorManager.remapCoordinateSystem(inR, x, y, outA)
                assertEquals(ok, SensorManagerMath.remapCoordinateSystem(inR, x, y, outB), ctx)
                assertBitsEqual(outA, outB, ctx)
                assertBitsEqual(inCopy, inR, ctx)
                if (ok) accepted++
            }
        }
        assertTrue(accepted > n / 10, "accepted $accepted")
        // Lengths other than 9 and 16 are 3 rows of 3: 12 works, 4 throws.
        for (length in intArrayOf(4, 12)) {
            val inR = vectorOf(rnd, length, 1f)
            assertSameOutcome { m -> m.remapCoordinateSystem(inR, SensorManagerMath.AXIS_Y, SensorManagerMath.AXIS_MINUS_X, FloatArray(length)) }
        }
    }

    @Test
    fun `remapCoordinateSystem in == out with 9 elements reproduces AOSP's in-place result, unlike a copy`() {
        // Documents the AOSP quirk the port reproduces: aliasing a 9-element matrix does NOT give the
        // same result as remapping a copy (for a remap that moves columns).
        val rnd = Random(6)
        val r = rotationMatrix(rnd, 9)
        val aliased = r.copyOf().also { SensorManager.remapCoordinateSystem(it, SensorManager.AXIS_Y, SensorManager.AXIS_MINUS_X, it) }
        val copied = FloatArray(9).also { SensorManager.remapCoordinateSystem(r, SensorManager.AXIS_Y, SensorManager.AXIS_MINUS_X, it) }
        val port = r.copyOf().also { SensorManagerMath.remapCoordinateSystem(it, SensorManagerMath.AXIS_Y, SensorManagerMath.AXIS_MINUS_X, it) }
        assertTrue(!aliased.contentEquals(copied), "AOSP in-place remap of 9 elements is expected to differ from a copy")
        assertBitsEqual(aliased, port) { "in-place" }
        // With 16 elements aliasing works in both.
        val r16 = rotationMatrix(rnd, 16)
        val aliased16 = r16.copyOf().also { SensorManagerMath.remapCoordinateSystem(it, SensorManagerMath.AXIS_Y, SensorManagerMath.AXIS_MINUS_X, it) }
        val copied16 = FloatArray(16).also { SensorManager.remapCoordinateSystem(r16, SensorManager.AXIS_Y, SensorManager.AXIS_MINUS_X, it) }
        assertBitsEqual(copied16, aliased16) { "16 aliased" }
    }

    @Test
    fun `remapCoordinateSystem in == out is thread-safe without AOSP's shared temp matrix`() {
        val rnd = Random(11)
        val inputs = Array(8) { rotationMatrix(rnd, 16) }
        val expected = inputs.map { FloatArray(16).also { out -> SensorManager.remapCoordinateSystem(it, SensorManager.AXIS_Y, SensorManager.AXIS_MINUS_X, out) } }
        val mismatches = java.util.concurrent.atomic.AtomicInteger()
        val threads = inputs.indices.map { t ->
            Thread {
                repeat(20_000) {
                    val r = inputs[t].copyOf()
                    SensorManagerMath.remapCoordinateSystem(r, SensorManagerMath.AXIS_Y, SensorManagerMath.AXIS_MINUS_X, r)
                    if (!r.contentEquals(expected[t])) mismatches.incrementAndGet()
                }
            }
        }
        threads.forEach { it.start() }
        threads.forEach { it.join() }
        assertEquals(0, mismatches.get())
    }

    @Test
    fun `getRotationMatrixFromVector matches for rotation vectors of 3, 4 and 5 elements and every layout`() {
        val rnd = Random(7)
        repeat(n) {
            val rv = rotationVector(rnd, 3 + it % 3)
            val length = intArrayOf(9, 16, 4, 12)[rnd.nextInt(4)] // 4 and 12 are left alone
            val a = garbage(rnd, length)
            val b = a.copyOf()
            SensorManager.getRotationMatrixFromVector(a, rv)
            SensorManagerMath.getRotationMatrixFromVector(b, rv)
            assertBitsEqual(a, b) { rv.contentToString() }
        }
        assertSameOutcome { m -> m.getRotationMatrixFromVector(FloatArray(9), FloatArray(2)) }
    }

    @Test
    fun `getQuaternionFromVector matches for 3, 4 and 5 elements, including Q == rv`() {
        val rnd = Random(8)
        repeat(n) {
            val rv = rotationVector(rnd, 3 + it % 3)
            val a = garbage(rnd, 4)
            val b = a.copyOf()
            SensorManager.getQuaternionFromVector(a, rv)
            SensorManagerMath.getQuaternionFromVector(b, rv)
            assertBitsEqual(a, b) { rv.contentToString() }
            if (rv.size >= 4) {
                val aliasA = rv.copyOf()
                val aliasB = rv.copyOf()
                SensorManager.getQuaternionFromVector(aliasA, aliasA)
                SensorManagerMath.getQuaternionFromVector(aliasB, aliasB)
                assertBitsEqual(aliasA, aliasB) { "aliased ${rv.contentToString()}" }
            }
        }
    }

    @Test
    fun `getAngleChange matches for 9 and 16 element pairs and ignored lengths`() {
        val rnd = Random(9)
        repeat(n) {
            // 12 elements is neither layout: AOSP reads such a matrix as zeros.
            val r = if (rnd.nextInt(20) == 0) vectorOf(rnd, 12, 1f) else rotationMatrix(rnd, if (rnd.nextBoolean()) 9 else 16)
            val prev = rotationMatrix(rnd, if (rnd.nextBoolean()) 9 else 16)
            val a = garbage(rnd, 3)
            val b = a.copyOf()
            SensorManager.getAngleChange(a, r, prev)
            SensorManagerMath.getAngleChange(b, r, prev)
            assertBitsEqual(a, b) { "${r.contentToString()} ${prev.contentToString()}" }
        }
    }

    @Test
    fun `getAltitude matches`() {
        val rnd = Random(10)
        repeat(n) {
            val p0 = if (it % 3 == 0) SensorManager.PRESSURE_STANDARD_ATMOSPHERE else 900f + rnd.nextFloat() * 200f
            val p = if (it % 50 == 0) specialScalar(rnd) else rnd.nextFloat() * 1100f
            assertBitsEqual(SensorManager.getAltitude(p0, p), SensorManagerMath.getAltitude(p0, p)) { "p0 $p0 p $p" }
        }
    }

    // ---- helpers ---------------------------------------------------------------------------

    private fun assertSameOutcome(call: (Ops) -> Unit) {
        fun outcome(ops: Ops): Any = try {
            call(ops); "ok"
        } catch (e: RuntimeException) {
            e::class
        }
        assertEquals(outcome(Ops.AOSP), outcome(Ops.PORT))
    }

    /** The two implementations behind one interface, for exception comparisons. */
    private enum class Ops {
        AOSP, PORT;

        fun getOrientation(r: FloatArray, v: FloatArray) {
            if (this == AOSP) SensorManager.getOrientation(r, v) else SensorManagerMath.getOrientation(r, v)
        }

        fun remapCoordinateSystem(inR: FloatArray, x: Int, y: Int, outR: FloatArray) {
            if (this == AOSP) SensorManager.remapCoordinateSystem(inR, x, y, outR) else SensorManagerMath.remapCoordinateSystem(inR, x, y, outR)
        }

        fun getRotationMatrixFromVector(r: FloatArray, rv: FloatArray) {
            if (this == AOSP) SensorManager.getRotationMatrixFromVector(r, rv) else SensorManagerMath.getRotationMatrixFromVector(r, rv)
        }
    }

    companion object {
        private val LAYOUTS = arrayOf(null, 9, 16, 9, 16, 4)
        private val VALID_AXES = intArrayOf(1, 2, 3, 129, 130, 131)

        fun assertBitsEqual(expected: FloatArray?, actual: FloatArray?, ctx: () -> String) {
            if (expected == null || actual == null) {
                assertEquals(expected == null, actual == null, ctx)
                return
            }
            assertEquals(expected.size, actual.size, ctx)
            for (i in expected.indices) {
                assertEquals(
                    java.lang.Float.floatToIntBits(expected[i]), java.lang.Float.floatToIntBits(actual[i]),
                ) { "element $i: ${expected[i]} vs ${actual[i]}; ${ctx()}" }
            }
        }

        fun assertBitsEqual(expected: Float, actual: Float, ctx: () -> String) =
            assertBitsEqual(floatArrayOf(expected), floatArrayOf(actual), ctx)

        fun vector(rnd: Random, scale: Float) = vectorOf(rnd, 3, scale)

        fun vectorOf(rnd: Random, size: Int, scale: Float) = FloatArray(size) { (rnd.nextFloat() * 2f - 1f) * scale }

        fun direction(rnd: Random, norm: Float): FloatArray {
            val v = FloatArray(3) { rnd.nextFloat() * 2f - 1f }
            val k = norm / kotlin.math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
            return FloatArray(3) { v[it] * k }
        }

        /** A norm whose square lies within a few ulps of AOSP's free-fall threshold 0.01·9.81². */
        fun freeFallEdge(rnd: Random): Float {
            var v = kotlin.math.sqrt(0.01f * 9.81f * 9.81f)
            val ulps = rnd.nextInt(-8, 9)
            repeat(kotlin.math.abs(ulps)) { v = if (ulps > 0) Math.nextUp(v) else Math.nextDown(v) }
            return v
        }

        /** A field nearly along gravity, so that |E × A| is around AOSP's 0.1 threshold. */
        fun nearlyParallel(rnd: Random, gravity: FloatArray): FloatArray {
            val k = rnd.nextFloat() * 8f
            val gNorm = kotlin.math.sqrt(gravity.sumOf { (it * it).toDouble() }).toFloat().coerceAtLeast(1e-3f)
            val offset = 0.2f / gNorm
            return FloatArray(3) { gravity[it] * k + (rnd.nextFloat() * 2f - 1f) * offset }
        }

        fun specialScalar(rnd: Random): Float = when (rnd.nextInt(8)) {
            0 -> 0f
            1 -> -0f
            2 -> Float.NaN
            3 -> Float.POSITIVE_INFINITY
            4 -> Float.MIN_VALUE
            5 -> 1e30f
            6 -> -1e-20f
            else -> rnd.nextFloat() * 10f
        }

        fun special(rnd: Random) = FloatArray(3) { specialScalar(rnd) }

        fun garbage(rnd: Random, size: Int) = FloatArray(size) { rnd.nextFloat() * 1000f - 500f }

        /** A random rotation matrix from AOSP's own rotation-vector conversion, in the given layout. */
        fun rotationMatrix(rnd: Random, length: Int): FloatArray =
            FloatArray(length).also { SensorManager.getRotationMatrixFromVector(it, rotationVector(rnd, 4)) }

        /** A rotation vector: a random unit quaternion (x, y, z, w), sometimes not unit, plus an accuracy. */
        fun rotationVector(rnd: Random, size: Int): FloatArray {
            val q = DoubleArray(4) { rnd.nextDouble() * 2 - 1 }
            val norm = kotlin.math.sqrt(q.sumOf { it * it }) * (if (rnd.nextInt(10) == 0) 0.9 else 1.0)
            return FloatArray(size) { if (it < 4) (q[it] / norm).toFloat() else rnd.nextFloat() }
        }

        fun axisArgument(rnd: Random): Int = when (rnd.nextInt(10)) {
            0 -> rnd.nextInt() // anything, mostly invalid
            1 -> intArrayOf(0, 4, 0x80, 0x83 or 0x100, -127, 0x7F)[rnd.nextInt(6)]
            else -> VALID_AXES[rnd.nextInt(VALID_AXES.size)]
        }
    }
}
