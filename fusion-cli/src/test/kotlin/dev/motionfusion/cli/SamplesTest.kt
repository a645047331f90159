package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.ByteArrayOutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path
import java.util.zip.GZIPInputStream
import java.util.zip.ZipFile

/**
 * The samples in samples/ are what these commands write (run from the repository root):
 *   bin/fusion simulate -o samples/sim-session.zip --duration 20 --rate 100 --seed 8
 *   bin/fusion simulate -o samples/sim-figure8.csv.gz --duration 20 --rate 100 --seed 8
 * This test makes them again and compares the contents (the app version in meta.json aside).
 */
class SamplesTest {
    @TempDir
    lateinit var dir: Path

    private val samples: Path = Path.of("..", "samples")

    private fun simulate(out: Path) {
        val o = ByteArrayOutputStream()
        val code = Cli(PrintStream(o), PrintStream(o)).run(listOf("simulate", "-o", out.toString(), "--duration", "20", "--rate", "100", "--seed", "8"))
        assertEquals(ExitCode.OK, code, o.toString())
    }

    private fun zipContents(p: Path): Map<String, String> = ZipFile(p.toFile()).use { z ->
        z.entries().asSequence().associate { e ->
            e.name to String(z.getInputStream(e).readBytes()).lines().filter { !it.contains("\"app_version\"") }.joinToString("\n")
        }
    }

    @Test
    fun `the session sample is reproducible and small`() {
        val committed = samples.resolve("sim-session.zip")
        assertTrue(Files.size(committed) < 300_000)
        val again = dir.resolve("sim-session.zip")
        simulate(again)
        assertEquals(zipContents(committed), zipContents(again))
    }

    @Test
    fun `the table sample is reproducible`() {
        val again = dir.resolve("sim-figure8.csv.gz")
        simulate(again)
        fun text(p: Path) = GZIPInputStream(Files.newInputStream(p)).use { String(it.readBytes()) }
        assertEquals(text(samples.resolve("sim-figure8.csv.gz")), text(again))
    }
}
