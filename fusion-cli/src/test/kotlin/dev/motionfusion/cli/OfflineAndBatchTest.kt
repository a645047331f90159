package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.nio.file.Files
import java.nio.file.Path

/** `--offline` (replay and eval) and many inputs in one `fusion replay`. */
class OfflineAndBatchTest {
    @TempDir
    lateinit var tmp: Path

    private fun p(name: String) = tmp.resolve(name).toString()

    private fun ok(vararg args: String): CliResult = fusion(*args).also { assertEquals(ExitCode.OK, it.code, it.err) }

    private fun mean(evalOut: String): Double = Regex("""\| \*\*mean\*\* \| \*\*([0-9.]+)\*\*""").find(evalOut)!!.groupValues[1].toDouble()

    private fun tempSpills(): Set<String> =
        File(System.getProperty("java.io.tmpdir")).list { _, n -> n.startsWith("fusion-offline-") }?.toSet() ?: emptySet()

    @Test
    fun `offline replay has the causal rows and columns and is closer to the truth, leaving no temporary file`() {
        ok("simulate", "--duration", "60", "--rate", "200", "-o", p("s"))
        val before = tempSpills()
        val causal = ok("replay", "--quiet", p("s"), "-o", p("c.csv"))
        val offline = ok("replay", "--quiet", "--offline", p("s"), "-o", p("o.csv"))
        assertEquals(causal.err, offline.err)
        val c = File(p("c.csv")).readLines()
        val o = File(p("o.csv")).readLines()
        assertEquals(c.size, o.size)
        assertEquals(c[0], o[0])
        assertEquals(c.map { it.substringBefore(',') }, o.map { it.substringBefore(',') })
        assertFalse(o.drop(1).any { it.contains("NaN") }, "every row has an orientation")
        assertEquals(before, tempSpills(), "the spill file is gone")
        val ec = mean(ok("eval", p("s")).out)
        val eo = mean(ok("eval", "--offline", p("s")).out)
        assertTrue(eo < 0.6 * ec, "offline $eo° against causal $ec°")
        // Each pass alone is as good as the causal filter (no one-sample shift in the backward pass).
        val back = mean(ok("eval", "--offline", "--offline-weight", "1", "--offline-smoothing", "0", p("s")).out)
        assertTrue(back < 1.3 * ec, "backward pass $back° against causal $ec°")
    }

    @Test
    fun `offline options are checked`() {
        assertEquals(ExitCode.USAGE, fusion("replay", "--offline-weight", "0.5", "x.csv").code)
        assertEquals(ExitCode.USAGE, fusion("replay", "--offline", "--offline-weight", "2", "x.csv").code)
        assertEquals(ExitCode.USAGE, fusion("replay", "--offline-smoothing", "0.5", "x.csv").code)
        assertEquals(ExitCode.USAGE, fusion("replay", "--offline", "--offline-smoothing", "-1", "x.csv").code)
    }

    @Test
    fun `several inputs replay into a folder, one output each, a bad one reported without stopping the others`() {
        val inputs = (1..3).map { k -> p("in/r$k.csv").also { File(it).parentFile.mkdirs(); ok("simulate", "--duration", "5", "--seed", "$k", "-o", it) } }
        File(p("in/bad.csv")).writeText("t_s,gx,gy,gz,ax,ay,az\n0,1,2\n")
        val r = fusion("replay", *inputs.toTypedArray(), p("in/bad.csv"), "-o", p("out") + "/", "--offline")
        assertEquals(ExitCode.DATA_ERROR, r.code, r.err)
        for (k in 1..3) {
            val single = ok("replay", "--quiet", "--offline", inputs[k - 1], "-o", p("single$k.csv"))
            assertEquals(File(p("single$k.csv")).readText(), File(p("out/r$k.csv")).readText(), single.err)
            assertTrue(r.err.contains("${inputs[k - 1]} → ${p("out/r$k.csv")}"), r.err)
        }
        assertFalse(File(p("out/bad.csv")).exists(), "nothing written for the bad input")
        assertEquals(setOf("r1.csv", "r2.csv", "r3.csv"), File(p("out")).list()!!.toSet(), "no temporary files left")
        assertTrue(r.err.contains("4 inputs: 3 ok, 1 failed"), r.err)
        assertTrue(r.err.contains("bad.csv: exit 1: "), r.err)
    }

    @Test
    fun `eval over several inputs scores each as alone, in input order, a bad one reported without stopping the others`() {
        val sessions = (1..3).map { k -> p("s$k").also { ok("simulate", "--duration", "8", "--seed", "$k", "-o", it) } }
        ok("simulate", "--duration", "5", "-o", p("plain.csv"))
        val r = fusion("eval", "--offline", sessions[0], p("plain.csv"), sessions[1], sessions[2])
        assertEquals(ExitCode.DATA_ERROR, r.code, r.err)
        val rows = r.out.lines().filter { it.startsWith("| ") && !it.startsWith("| trial") && !it.contains("**mean**") }
        assertEquals(3, rows.size, r.out)
        for (k in 1..3) {
            val alone = ok("eval", "--offline", sessions[k - 1]).out.lines().single { it.startsWith("| ") && !it.startsWith("| trial") && !it.contains("**mean**") }
            assertEquals(alone, rows[k - 1], "session $k as alone, in input order")
        }
        assertTrue(r.err.contains("4 inputs: 3 ok, 1 failed"), r.err)
        assertTrue(r.err.contains("plain.csv: exit ${ExitCode.DATA_ERROR}: ") && r.err.contains("no truth.csv"), r.err)
        val allBad = fusion("eval", p("plain.csv"))
        assertEquals(ExitCode.DATA_ERROR, allBad.code)
        assertEquals("", allBad.out)
        assertFalse(allBad.err.contains("inputs:"), "one input: its error alone, no summary: ${allBad.err}")
    }

    @Test
    fun `two inputs of one name, or an output onto an input, are usage errors before anything is written`() {
        Files.createDirectories(tmp.resolve("a"))
        Files.createDirectories(tmp.resolve("b"))
        ok("simulate", "--duration", "5", "-o", p("a/x.csv"))
        ok("simulate", "--duration", "5", "-o", p("b/x.csv"))
        ok("simulate", "--duration", "5", "-o", p("b/y.csv"))
        val same = fusion("replay", p("a/x.csv"), p("b/x.csv"), "-o", p("out") + "/")
        assertEquals(ExitCode.USAGE, same.code)
        assertTrue(same.err.contains("would both be written"), same.err)
        val onto = fusion("replay", p("a/x.csv"), p("b/y.csv"), "-o", p("a/"))
        assertEquals(ExitCode.USAGE, onto.code)
        assertTrue(onto.err.contains("is the input"), onto.err)
        assertEquals(listOf("x.csv"), File(p("a")).list()!!.toList())
        assertFalse(File(p("out")).exists(), "a refused batch makes no folder")
    }
}
