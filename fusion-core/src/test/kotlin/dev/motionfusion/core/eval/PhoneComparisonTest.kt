package dev.motionfusion.core.eval

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.util.Locale

class PhoneComparisonTest {
    @TempDir
    lateinit var dir: File

    private fun q(v: Quaternion) = String.format(Locale.ROOT, "%.9f,%.9f,%.9f,%.9f", v.w, v.x, v.y, v.z)

    /** A trial of [n] rows whose truth is [truth]; rows 0 and 1 are not scored. */
    private fun trial(n: Int, truth: Quaternion): File {
        File(dir, "input.csv").writeText("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" + (0 until n).joinToString("") { "${it * 0.01},0,0,0,0,0,9.8,0,20,-40\n" })
        File(dir, "truth.csv").writeText("t_s,qw,qx,qy,qz,movement\n" + (0 until n).joinToString("") { "${it * 0.01},${q(truth)},${if (it < 2) 0 else 1}\n" })
        return dir
    }

    @Test
    fun `scores the rotation vector against the truth with heading and inclination apart`() {
        val truth = Quaternion.fromAxisAngle(Vector3(0.3, 0.2, 1.0), 0.7)
        val d = trial(10, truth)
        val t = Trial.load(d)
        assertNull(PhoneComparison.rotationVector(d, t))
        // 10° off in heading (about the earth's vertical), 4° in tilt (about east), one row missing.
        val rv = Quaternion.fromAxisAngle(Vector3(1.0, 0.0, 0.0), Math.toRadians(4.0)) * Quaternion.fromAxisAngle(Vector3(0.0, 0.0, 1.0), Math.toRadians(10.0)) * truth
        File(d, "rotation_vector.csv").writeText("t_s,qw,qx,qy,qz\n" + (0 until 10).filter { it != 5 }.joinToString("") { "${it * 0.01},${q(rv)}\n" })
        val e = PhoneComparison.rotationVector(d, t)!!
        assertEquals(7, e.samples)
        assertEquals(10.0, e.headingDeg, 0.1)
        assertEquals(4.0, e.inclinationDeg, 0.1)
        val r = Evaluation.evaluate(t, dev.motionfusion.core.filter.FilterSettings())
        val table = PhoneComparison.table(listOf(r, r.copy(trial = "other")), mapOf(t.name to e))
        assertTrue(table.lines()[2].endsWith(String.format(Locale.ROOT, "| %.2f | 10.00 | 4.00 |", e.totalDeg)), table)
        assertTrue(table.lines()[3].startsWith("| other |") && table.lines()[3].endsWith("|  |  |  |"), table)
        assertTrue("mean of the 1 with a rotation vector" in table, table)
    }
}
