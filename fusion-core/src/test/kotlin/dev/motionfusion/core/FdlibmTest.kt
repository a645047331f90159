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
}
