package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.util.Random

class FdlibmTest {
    private fun same(x: Double) = assertEquals(StrictMath.asin(x).toRawBits(), Fdlibm.asin(x).toRawBits(), "asin($x)")

    @Test
    fun `asin is StrictMath asin bit for bit`() {
        val r = Random(17)
        repeat(2_000_000) {
            same(r.nextDouble() * 2 - 1) // uniform in (-1, 1)
            same(Math.scalb(r.nextDouble(), -r.nextInt(60)) * (if (r.nextBoolean()) 1 else -1)) // every scale down to 2^-60
            same(Double.fromBits(r.nextLong())) // any double, most |x| > 1: NaN
        }
        // The branch points of the algorithm and their neighbours.
        for (b in doubleArrayOf(0.0, 0.5, 0.975, 1.0, Math.scalb(1.0, -27), Math.scalb(1.0, -26), Double.fromBits(0x3FEF333300000000L))) {
            var x = b
            repeat(50) { same(x); same(-x); x = Math.nextDown(x) }
            x = b
            repeat(50) { same(x); same(-x); x = Math.nextUp(x) }
        }
        for (x in doubleArrayOf(Double.NaN, Double.POSITIVE_INFINITY, Double.NEGATIVE_INFINITY, -0.0, Double.MIN_VALUE, 1.0000000000000002)) same(x)
    }

    private fun same(y: Double, x: Double) =
        assertEquals(StrictMath.atan2(y, x).toRawBits(), Fdlibm.atan2(y, x).toRawBits(), "atan2($y, $x)")

    @Test
    fun `atan2 and atan are StrictMath's bit for bit`() {
        val r = Random(18)
        repeat(1_000_000) {
            same(r.nextGaussian(), r.nextGaussian()) // every quadrant, every ratio near 1
            same(Math.scalb(r.nextGaussian(), r.nextInt(140) - 70), Math.scalb(r.nextGaussian(), r.nextInt(140) - 70)) // ratios beyond 2^±60
            same(Double.fromBits(r.nextLong()), Double.fromBits(r.nextLong())) // any doubles, NaN and infinities among them
            val x = Math.scalb(r.nextDouble(), r.nextInt(80) - 40) * (if (r.nextBoolean()) 1 else -1)
            assertEquals(StrictMath.atan(x).toRawBits(), Fdlibm.atan(x).toRawBits(), "atan($x)")
        }
        // atan's reduction points (7/16, 11/16, 19/16, 39/16, 2^-29, 2^66) and their neighbours, through atan2(t, 1) and atan2(t, 2).
        for (b in doubleArrayOf(7.0 / 16, 11.0 / 16, 19.0 / 16, 39.0 / 16, Math.scalb(1.0, -29), Math.scalb(1.0, 66))) {
            var t = Math.nextDown(Math.nextDown(b))
            repeat(5) {
                for (s in doubleArrayOf(t, -t)) { same(s, 1.0); same(2 * s, 2.0); same(s, -1.0) }
                t = Math.nextUp(t)
            }
        }
        val special = doubleArrayOf(0.0, -0.0, 1.0, -1.0, Double.POSITIVE_INFINITY, Double.NEGATIVE_INFINITY, Double.NaN, Double.MIN_VALUE, Double.MAX_VALUE, 1e-300, -1e300)
        for (y in special) for (x in special) same(y, x)
    }
}
