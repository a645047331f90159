package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale

/** `fusion align` on simulated phones whose clocks are apart by a known offset (docs/SYNC.md). */
class AlignCommandTest {
    @TempDir
    lateinit var dir: Path

    private fun p(name: String) = dir.resolve(name).toString()

    /** A simulated IMU table with [violent] motions, its times shifted by [shiftS]. */
    private fun phone(name: String, seed: Int, rate: Int, shiftS: Double, violent: String? = "shake@8,drop@14"): String {
        val raw = p("raw-$name")
        val args = mutableListOf("simulate", "-o", raw, "--duration", "20", "--rate", "$rate", "--seed", "$seed")
        if (violent != null) args += listOf("--violent", violent)
        val r = fusion(*args.toTypedArray())
        assertEquals(ExitCode.OK, r.code, r.err)
        val lines = Files.readAllLines(Path.of(raw))
        val shifted = listOf(lines[0]) + lines.drop(1).map { line ->
            val comma = line.indexOf(',')
            String.format(Locale.ROOT, "%.9f", line.substring(0, comma).toDouble() + shiftS) + line.substring(comma)
        }
        Files.write(Path.of(p(name)), shifted)
        return p(name)
    }

    @Test
    fun `a shared shake gives the offset between two phones within one sample period`() {
        // Two phones with their own smooth motion around one shake and one drop, at 200 and 100 Hz, 2.345678 s apart.
        val a = phone("a.csv", seed = 8, rate = 200, shiftS = 0.0)
        val b = phone("b.csv", seed = 9, rate = 100, shiftS = 2.345678)
        val r = fusion("align", a, b, "-o", p("offsets.csv"))
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue(r.out.contains("| gyro |"), r.out)
        val row = Files.readAllLines(Path.of(p("offsets.csv")))[2].split(',')
        assertEquals("gyro", row[1])
        val offset = row[2].toLong()
        assertTrue(Math.abs(offset + 2_345_678_000L) <= 10_000_000, "offset $offset ns")
        // The same through the other order: the sign turns.
        val back = fusion("align", b, a, "--method", "gyro")
        assertEquals(ExitCode.OK, back.code, back.err)
        assertTrue(back.out.contains("| 2.34"), back.out)
    }

    @Test
    fun `without a shared motion the gyroscopes cannot tell and say so`() {
        val a = phone("a.csv", seed = 8, rate = 100, shiftS = 0.0, violent = null)
        val b = phone("b.csv", seed = 9, rate = 100, shiftS = 1.0, violent = null)
        val r = fusion("align", a, b, "--method", "gyro", "-o", p("offsets.csv"))
        assertEquals(ExitCode.DATA_ERROR, r.code, r.out + r.err)
        assertTrue(r.err.contains("no shared motion that singles one offset out"), r.err)
        assertFalse(Files.exists(Path.of(p("offsets.csv"))))
    }

    @Test
    fun `auto without wall clocks fails where the gyroscopes only guess, and --max-lag bounds the search`() {
        val a = phone("a.csv", seed = 8, rate = 100, shiftS = 0.0, violent = null)
        val b = phone("b.csv", seed = 9, rate = 100, shiftS = 1.0, violent = null)
        val guess = fusion("align", a, b, "-o", p("guess.csv"))
        assertEquals(ExitCode.DATA_ERROR, guess.code, guess.out + guess.err)
        assertFalse(Files.exists(Path.of(p("guess.csv"))))
        // A shared shake 2.5 s apart, searched within 0.3 s of 0: the window's best is no peak, and no offset outside it is given.
        val c = phone("c.csv", seed = 8, rate = 100, shiftS = 0.0)
        val d = phone("d.csv", seed = 9, rate = 100, shiftS = 2.5)
        val narrow = fusion("align", c, d, "--max-lag", "0.3", "--method", "gyro")
        assertEquals(ExitCode.DATA_ERROR, narrow.code, narrow.out + narrow.err)
        assertTrue("the best at the edge of the --max-lag window" in narrow.err || "no rival in a window this narrow" in narrow.err, narrow.err)
        val offset = narrow.out.lines().first { it.startsWith("| d.csv") }.split('|')[3].trim().toDouble()
        assertTrue(Math.abs(offset) <= 0.3, "the offset stays in the window: $offset")
        // Wide enough, the same pair is found.
        assertEquals(ExitCode.OK, fusion("align", c, d, "--max-lag", "5", "--method", "gyro").code)
    }

    @Test
    fun `sessions use their wall clocks where the motion cannot tell`() {
        for (n in listOf("s1.zip", "s2.zip")) assertEquals(ExitCode.OK, fusion("simulate", "-o", p(n), "--duration", "10", "--seed", if (n == "s1.zip") "3" else "4").code)
        val r = fusion("align", p("s1.zip"), p("s2.zip"))
        assertEquals(ExitCode.OK, r.code, r.err)
        // The simulator notes the same wall clock for both: 0 s apart, the same sensor clock.
        assertTrue(r.out.contains("| utc | 0.000000 |  |  | 0.000000 |"), r.out + r.err)
        val u = fusion("align", p("s1.zip"), p("s2.zip"), "--method", "utc")
        assertEquals(ExitCode.OK, u.code, u.err)
        val table = phone("t.csv", seed = 8, rate = 100, shiftS = 0.0)
        val noUtc = fusion("align", p("s1.zip"), table, "--method", "utc")
        assertEquals(ExitCode.DATA_ERROR, noUtc.code)
        assertTrue(noUtc.err.contains("no wall-clock anchor"), noUtc.err)
    }

    @Test
    fun `wrong command lines are refused before anything is read`() {
        assertEquals(ExitCode.USAGE, fusion("align", p("a.csv")).code)
        assertEquals(ExitCode.USAGE, fusion("align", p("a.csv"), p("b.csv"), "--method", "ntp").code)
        assertEquals(ExitCode.USAGE, fusion("align", p("a.csv"), p("b.csv"), "--max-lag", "-1").code)
        val a = phone("a.csv", seed = 8, rate = 100, shiftS = 0.0)
        val before = Files.readAllBytes(Path.of(a))
        val onto = fusion("align", a, phone("b.csv", seed = 9, rate = 100, shiftS = 0.0), "-o", a)
        assertEquals(ExitCode.USAGE, onto.code, onto.err)
        assertTrue(before.contentEquals(Files.readAllBytes(Path.of(a))))
    }
}
