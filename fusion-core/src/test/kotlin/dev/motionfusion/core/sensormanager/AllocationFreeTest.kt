package dev.motionfusion.core.sensormanager

import dev.motionfusion.core.RotationArrays
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.lang.management.ManagementFactory
import kotlin.random.Random

/**
 * The array paths allocate nothing: the bytes this thread allocates (HotSpot's
 * com.sun.management.ThreadMXBean.getCurrentThreadAllocatedBytes) are measured around 200,000
 * calls of each function, after a warm-up that lets the JIT compile them, with inputs prepared
 * beforehand. A single FloatArray(9) per call would be 200,000 × 56 bytes ≈ 11 MB; the
 * measurement itself costs a few hundred bytes, so the budget is under 0.05 byte per call.
 */
class AllocationFreeTest {

    /** A call taking the iteration number; a fun interface on a primitive Int, so nothing is boxed. */
    fun interface Call {
        fun run(i: Int)
    }

    private val threadBean = ManagementFactory.getThreadMXBean() as com.sun.management.ThreadMXBean
    private val calls = 200_000

    private val rnd = Random(42)
    private val inputs = Array(64) { FloatArray(3) { rnd.nextFloat() * 20f - 10f } }
    private val fields = Array(64) { FloatArray(3) { rnd.nextFloat() * 100f - 50f } }
    private val rotationVectors = Array(64) { SensorManagerMathDifferentialTest.rotationVector(rnd, 3 + it % 3) }
    private val r9 = FloatArray(9)
    private val r16 = FloatArray(16)
    private val i9 = FloatArray(9)
    private val prev = FloatArray(9)
    private val out3 = FloatArray(3)
    private val q4 = FloatArray(4)
    private val qd = DoubleArray(4)
    private var sink: FloatArray? = null

    private fun bytesPerCall(name: String, body: Call): Double {
        for (k in 0 until calls) body.run(k) // warm-up
        val before = threadBean.currentThreadAllocatedBytes
        for (k in 0 until calls) body.run(k)
        val after = threadBean.currentThreadAllocatedBytes
        return (after - before).toDouble() / calls.also { println("$name: ${after - before} bytes in $calls calls") }
    }

    private fun assertAllocationFree(name: String, body: Call) {
        val perCall = bytesPerCall(name, body)
        assertTrue(perCall < 0.05, "$name allocates $perCall bytes per call")
    }

    @Test
    fun `the harness detects a function that allocates`() {
        // The array escapes into a field, so escape analysis cannot remove the allocation.
        assertTrue(bytesPerCall("FloatArray(9)") { sink = FloatArray(9) } > 16.0)
    }

    @Test
    fun `SensorManagerMath allocates nothing`() {
        assertAllocationFree("getRotationMatrix") {
            SensorManagerMath.getRotationMatrix(if (it % 2 == 0) r9 else r16, i9, inputs[it and 63], fields[it and 63])
        }
        assertAllocationFree("getInclination") { out3[0] = SensorManagerMath.getInclination(i9) }
        assertAllocationFree("getOrientation") { SensorManagerMath.getOrientation(if (it % 2 == 0) r9 else r16, out3) }
        assertAllocationFree("remapCoordinateSystem") {
            SensorManagerMath.remapCoordinateSystem(r9, SensorManagerMath.AXIS_Y, SensorManagerMath.AXIS_MINUS_X, prev)
        }
        assertAllocationFree("remapCoordinateSystem in == out, 16") {
            SensorManagerMath.remapCoordinateSystem(r16, SensorManagerMath.AXIS_Y, SensorManagerMath.AXIS_MINUS_X, r16)
        }
        assertAllocationFree("getAngleChange") { SensorManagerMath.getAngleChange(out3, r9, prev) }
        assertAllocationFree("getRotationMatrixFromVector") {
            SensorManagerMath.getRotationMatrixFromVector(if (it % 2 == 0) r9 else r16, rotationVectors[it and 63])
        }
        assertAllocationFree("getQuaternionFromVector") { SensorManagerMath.getQuaternionFromVector(q4, rotationVectors[it and 63]) }
        assertAllocationFree("getAltitude") { out3[0] = SensorManagerMath.getAltitude(1013.25f, 900f + (it and 63)) }
    }

    @Test
    fun `RotationArrays allocates nothing`() {
        assertAllocationFree("rotationMatrixToQuaternion") {
            SensorManagerMath.getRotationMatrixFromVector(r9, rotationVectors[it and 63])
            RotationArrays.rotationMatrixToQuaternion(r9, qd)
        }
        assertAllocationFree("quaternionToRotationMatrix") { RotationArrays.quaternionToRotationMatrix(qd, if (it % 2 == 0) r9 else r16) }
    }
}
