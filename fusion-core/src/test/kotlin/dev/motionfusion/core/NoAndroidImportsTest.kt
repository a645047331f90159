package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File

/** fusion-core's boundary: no file under src/main may import android.* (only the app touches Android). */
class NoAndroidImportsTest {

    private val mainSources = File("src/main")

    @Test
    fun `no file under src main imports android`() {
        val files = mainSources.walkTopDown().filter { it.isFile }.toList()
        assertTrue(files.count { it.extension == "kt" } >= 5, "expected the sources under ${mainSources.absolutePath}")
        val offenders = files.flatMap { f -> androidImports(f.readText()).map { "${f.path}: $it" } }
        assertEquals(emptyList<String>(), offenders)
    }

    @Test
    fun `the scan finds android imports wherever they are`() {
        val text = "package x\nimport kotlin.math.sin\nimport android.hardware.SensorManager\n  import android.util.Log as L\n// import androidx.core\n"
        assertEquals(listOf("import android.hardware.SensorManager", "import android.util.Log as L"), androidImports(text))
    }

    private fun androidImports(text: String): List<String> =
        text.lines().map { it.trim() }.filter { it.startsWith("import android.") }
}
