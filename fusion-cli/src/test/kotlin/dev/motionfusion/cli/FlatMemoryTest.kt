package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.TimeUnit

/**
 * Every command that reads or writes a recording streams: each runs on an hour of 100 Hz data
 * (360,000 samples) in a separate JVM limited to a 64 MB heap, where anything held in memory
 * per sample would end in OutOfMemoryError.
 */
class FlatMemoryTest {
    @TempDir
    lateinit var tmp: Path

    private fun fusionForked(vararg args: String): CliResult {
        val java = File(System.getProperty("java.home"), "bin/java").path
        val out = tmp.resolve("stdout-${args[0]}").toFile()
        val err = tmp.resolve("stderr-${args[0]}").toFile()
        val p = ProcessBuilder(listOf(java, "-Xmx64m", "-cp", System.getProperty("java.class.path"), "dev.motionfusion.cli.MainKt") + args)
            .redirectOutput(out).redirectError(err).start()
        assertTrue(p.waitFor(10, TimeUnit.MINUTES), "fusion ${args.joinToString(" ")} did not finish")
        return CliResult(p.exitValue(), out.readText(), err.readText())
    }

    private fun ok(vararg args: String): CliResult {
        val r = fusionForked(*args)
        assertEquals(ExitCode.OK, r.code, "fusion ${args.joinToString(" ")}: ${r.err}")
        assertTrue(!r.err.contains("OutOfMemoryError"), r.err)
        return r
    }

    @Test
    fun `an hour of data runs through every command in a 64 MB heap`() {
        val session = tmp.resolve("hour").toString()
        val table = tmp.resolve("hour.csv").toString()
        ok("simulate", "--duration", "3600", "--rate", "100", "-o", session)
        ok("simulate", "--duration", "3600", "--rate", "100", "-o", table)
        val replayed = tmp.resolve("replay.csv").toString()
        ok("replay", "--quiet", table, "-o", replayed)
        assertEquals(360_001L, Files.lines(java.nio.file.Paths.get(replayed)).use { it.count() })
        // A trial folder of an hour: the table and, as its truth, the replay's own orientation.
        val trial = Files.createDirectories(tmp.resolve("trials/hour"))
        Files.copy(java.nio.file.Paths.get(table), trial.resolve("input.csv"))
        Files.copy(java.nio.file.Paths.get(replayed), trial.resolve("truth.csv"))
        val e = ok("eval", trial.toString())
        assertTrue(e.out.contains("| hour | 0.00 |"), e.out)
        ok("eval", session)
        val t = ok("eval", "--truth", replayed, replayed)
        assertTrue(t.out.contains("| replay.csv | 0.00 |"), t.out)
        ok("plot", session, "-o", tmp.resolve("hour.svg").toString())
        // The offline estimate of an hour at 200 Hz (720,000 rows): its backward pass reads a temporary file.
        val table200 = tmp.resolve("hour200.csv").toString()
        ok("simulate", "--duration", "3600", "--rate", "200", "-o", table200)
        val offline = tmp.resolve("offline.csv").toString()
        ok("replay", "--quiet", "--offline", table200, "-o", offline)
        assertEquals(720_001L, Files.lines(java.nio.file.Paths.get(offline)).use { it.count() })
        ok("compare", session)
    }
}
