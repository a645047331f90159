package dev.motionfusion.app.build

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.File
import java.nio.file.Files
import java.nio.file.StandardCopyOption

/**
 * The Android Studio project is not built here, so GradleMirror (structural reading of the Gradle
 * scripts against the poms) is what keeps it runnable. The first test checks the repository; each
 * other test puts one known defect back into a copy of the build files and shows the checker
 * reports it, so that none of these checks can pass by not looking.
 */
class AndroidStudioProjectTest {
    @TempDir
    lateinit var copy: File

    private val root = BuildFiles.repositoryRoot

    @Test
    fun `the Gradle files mirror the Maven build`() {
        assertEquals(emptyList<String>(), GradleMirror(root, BuildFiles.localRepository).problems())
    }

    // --- the defect put back into a copy ---

    private fun copyRepository() {
        // Outputs of either build (a module's target/ or build/), not the package folders named build.
        val skip = setOf(".git", "target", "build", ".gradle", ".kotlin", ".idea")
        val topLevel = { d: File -> d.parentFile == root || d.parentFile?.parentFile == root }
        root.walkTopDown().onEnter { it == root || it.name !in skip || !topLevel(it) }.filter { it.isFile }.forEach { f ->
            val to = File(copy, f.relativeTo(root).path)
            to.parentFile.mkdirs()
            Files.copy(f.toPath(), to.toPath(), StandardCopyOption.COPY_ATTRIBUTES)
        }
    }

    private fun edit(path: String, old: String, new: String) {
        val f = File(copy, path)
        val text = f.readText()
        assertTrue(text.contains(old), "$path no longer holds the text this regression changes: $old")
        f.writeText(text.replace(old, new))
    }

    private fun problems(mavenOnlyDependencies: Map<String, String> = emptyMap()): List<String> =
        GradleMirror(copy, BuildFiles.localRepository, mavenOnlyDependencies = mavenOnlyDependencies).problems()

    /** Copies the repository, applies [change], and asserts a problem containing [expected] is reported. */
    private fun reports(expected: String, mavenOnlyDependencies: Map<String, String> = emptyMap(), change: () -> Unit) {
        copyRepository()
        change()
        val found = problems(mavenOnlyDependencies)
        assertTrue(found.any { expected in it }, "expected a problem with '$expected', got:\n" + found.joinToString("\n"))
    }

    @Test
    fun `an unchanged copy has no problems`() {
        copyRepository()
        assertEquals(emptyList<String>(), problems())
    }

    @Test
    fun `no gradle properties`() = reports("gradle.properties is missing") { File(copy, "gradle.properties").delete() }

    @Test
    fun `no AndroidX flag`() = reports("android.useAndroidX=true is not set") { edit("gradle.properties", "android.useAndroidX=true", "android.useAndroidX=false") }

    @Test
    fun `a daemon heap too small for R8`() = reports("R8 needs at least -Xmx3g") { edit("gradle.properties", "-Xmx4g", "-Xmx512m") }

    @Test
    fun `a toolchain without a resolver`() = reports("no toolchain resolver") {
        edit("settings.gradle.kts", "    id(\"org.gradle.toolchains.foojay-resolver-convention\") version \"0.9.0\"\n", "")
    }

    @Test
    fun `a test source importing a Maven-only dependency`() =
        reports("ApiLevelGuardTest.kt imports org.codehaus.mojo.animal_sniffer.SignatureChecker", mapOf("org.codehaus.mojo:animal-sniffer" to "not needed by Gradle")) {
            edit("app/build.gradle.kts", "    testImplementation(libs.animal.sniffer)\n", "")
        }

    @Test
    fun `JUnit 6 without the platform launcher`() = reports("fusion-cli/build.gradle.kts: no testRuntimeOnly(\"org.junit.platform:junit-platform-launcher\")") {
        edit("fusion-cli/build.gradle.kts", "    testRuntimeOnly(libs.junit.platform.launcher)\n", "")
    }

    @Test
    fun `a Surefire system property without a Gradle counterpart`() = reports("Surefire's system property project.root has no systemProperty") {
        edit("app/build.gradle.kts", "    systemProperty(\"project.root\", rootDir.path)\n", "")
    }

    @Test
    fun `a Surefire property added to a pom is asked of Gradle too`() = reports("Surefire's system property robolectric.sdk has no systemProperty") {
        edit("app/pom.xml", "<robolectric.offline>true</robolectric.offline>", "<robolectric.offline>true</robolectric.offline><robolectric.sdk>35</robolectric.sdk>")
    }

    @Test
    fun `a literal Surefire value that differs`() = reports("systemProperty(\"robolectric.offline\") is false") {
        edit("app/build.gradle.kts", "systemProperty(\"robolectric.offline\", \"true\")", "systemProperty(\"robolectric.offline\", \"false\")")
    }

    @Test
    fun `a test reading a Maven-only property that Gradle runs`() = reports("LibraryTreeTest.kt reads maven.repo.local") {
        edit("app/build.gradle.kts", "        excludeTestsMatching(\"dev.motionfusion.app.build.LibraryTreeTest\")\n", "")
    }

    @Test
    fun `no add-opens for Robolectric`() = reports("JVM flag --add-opens java.base/java.io=ALL-UNNAMED is not in the test task's jvmArgs") {
        edit("app/build.gradle.kts", "    jvmArgs(\"--add-opens\", \"java.base/java.io=ALL-UNNAMED\")\n", "")
    }

    @Test
    fun `not the heap of Surefire`() = reports("Surefire runs the tests with -Xmx3g") { edit("app/build.gradle.kts", "    maxHeapSize = \"3g\"\n", "") }

    @Test
    fun `the heap of the root pom reaches the JVM modules`() = reports("fusion-core/build.gradle.kts: Surefire runs the tests with -Xmx2g") {
        edit("fusion-core/build.gradle.kts", "    maxHeapSize = \"2g\"\n", "")
    }

    @Test
    fun `Kotlin 2_4 with the R8 bundled with AGP 8_7`() = reports("Kotlin 2.4.21 needs R8 9.1.29 or newer") {
        edit("settings.gradle.kts", "            classpath(\"com.android.tools:r8:9.5.28\")\n", "")
    }

    @Test
    fun `an R8 other than Maven's`() = reports("pins R8 9.1.30, Maven runs 9.5.28") { edit("settings.gradle.kts", "r8:9.5.28", "r8:9.1.30") }

    @Test
    fun `the R8 pin back in the root buildscript`() = reports("build.gradle.kts pins com.android.tools:r8 in its buildscript") {
        edit("settings.gradle.kts", "            classpath(\"com.android.tools:r8:9.5.28\")\n", "")
        edit("build.gradle.kts", "plugins {", "buildscript {\n    dependencies {\n        classpath(\"com.android.tools:r8:9.5.28\")\n    }\n}\n\nplugins {")
    }

    // --- the six regressions of issue 37, each invisible to the checker before it read what the files mean ---

    @Test
    fun `a release build without minification or ProGuard files`() {
        copyRepository()
        edit("app/build.gradle.kts", "            isMinifyEnabled = true\n            proguardFiles(\"proguard-rules.pro\")\n", "            isMinifyEnabled = false\n")
        val found = problems()
        assertTrue(found.any { "isMinifyEnabled = false" in it }, found.joinToString("\n"))
        assertTrue(found.any { "proguardFiles do not name proguard-rules.pro" in it }, found.joinToString("\n"))
    }

    @Test
    fun `the wrapper raised to 8_12 with the old checksum`() = reports("is not the SHA-256 Gradle publishes for gradle-8.12-bin.zip") {
        edit("gradle/wrapper/gradle-wrapper.properties", "gradle-8.11.1-bin.zip", "gradle-8.12-bin.zip")
    }

    @Test
    fun `a well-formed wrong checksum`() = reports("distributionSha256Sum 0000000000000000000000000000000000000000000000000000000000000000 is not the SHA-256") {
        edit("gradle/wrapper/gradle-wrapper.properties", "f397b287023acdba1e9f6fc5ea72d22dd63669d59ed4a289a29b1a76eee151c6", "0".repeat(64))
    }

    @Test
    fun `a packaging exclude that drops the ServiceLoader files`() = reports("packaging excludes \"META-INF/services/**\", which drops") {
        edit("app/build.gradle.kts", "    compileOptions {", "    packaging {\n        resources {\n            excludes += \"META-INF/services/**\"\n        }\n    }\n\n    compileOptions {")
    }

    @Test
    fun `a debug build type without a signing config`() = reports("the debug build type's signingConfig is null") {
        edit("app/build.gradle.kts", "            signingConfig = signingConfigs.getByName(\"debug\")", "            signingConfig = null")
    }

    @Test
    fun `a toolchain resolver version that does not exist`() = reports("plugin org.gradle.toolchains.foojay-resolver-convention 0.99.0 is not a published version") {
        edit("settings.gradle.kts", "foojay-resolver-convention\") version \"0.9.0\"", "foojay-resolver-convention\") version \"0.99.0\"")
    }

    // --- the rest of what the checker reads ---

    @Test
    fun `a Gradle release missing from the table`() = reports("Gradle 8.99 (bin) is not in gradle/gradle-releases.tsv") {
        edit("gradle/wrapper/gradle-wrapper.properties", "gradle-8.11.1-bin.zip", "gradle-8.99-bin.zip")
    }

    @Test
    fun `a module without a POM from a repository that wants one`() = reports("gummy-bears-api-26:0.12.0 is published without a POM") {
        edit("settings.gradle.kts", "                    metadataSources {\n                        artifact()\n                    }\n", "")
    }

    @Test
    fun `a lambda argument provider`() = reports("a lambda CommandLineArgumentProvider") {
        edit("app/build.gradle.kts", "    jvmArgumentProviders.add(objects.newInstance<SystemPropertyFile>().apply {\n        propertyName.set(name)\n        this.file.set(file)\n    })",
            "    inputs.file(file)\n    jvmArgumentProviders.add(CommandLineArgumentProvider { listOf(\"-D\$name=\${file.get().asFile.absolutePath}\") })")
    }

    @Test
    fun `a file input without path sensitivity`() = reports("SystemPropertyFile.file has no @get:PathSensitive") {
        edit("app/build.gradle.kts", "    @get:InputFile\n    @get:PathSensitive(PathSensitivity.NONE)\n", "    @get:InputFile\n")
    }

    @Test
    fun `slf4j-api left at Java-WebSocket's version`() = reports("Maven's dependencyManagement sets org.slf4j:slf4j-api to 2.0.16") {
        edit("fusion-stream/build.gradle.kts", "    constraints {\n        implementation(libs.slf4j.api)\n    }\n", "")
    }

    @Test
    fun `signing schemes that differ from apksigner's`() = reports("enableV3Signing = false; the Maven build signs with --v3-signing-enabled true") {
        edit("app/build.gradle.kts", "enableV3Signing = true", "enableV3Signing = false")
    }

    @Test
    fun `a signing scheme left to the defaults`() = reports("the debug signingConfig does not set enableV4Signing") {
        edit("app/build.gradle.kts", "            enableV4Signing = false\n", "")
    }

    @Test
    fun `the merger's tools libraries of another AGP`() = reports("android-tools is 31.7.2; AGP 8.7.3's tools libraries are 31.7.3") {
        edit("gradle/libs.versions.toml", "android-tools = \"31.7.3\"", "android-tools = \"31.7.2\"")
    }

    @Test
    fun `a Kotlin version without a compatibility row`() = reports("no row for Kotlin 2.4") {
        edit("gradle/compatibility.tsv", "kotlin    2.4", "kotlin    9.9")
    }

    @Test
    fun `the CLI's version properties not expanded`() = reports("dev/motionfusion/cli/version.properties is filtered by Maven") {
        edit("fusion-cli/build.gradle.kts", "filesMatching(\"**/version.properties\")", "filesMatching(\"**/other.properties\")")
    }

    @Test
    fun `an expand without the placeholder's value`() = reports("expand(…) does not give \${project.version}") {
        edit("fusion-cli/build.gradle.kts", "mapOf(\"version\" to version)", "mapOf(\"name\" to version)")
    }

    @Test
    fun `Robolectric's filtered config where Gradle copies it unexpanded`() = reports("Gradle copies it unexpanded") {
        edit("app/pom.xml", "<directory>src/test/maven-resources</directory>", "<directory>src/test/resources</directory>")
        val from = File(copy, "app/src/test/maven-resources/com/android/tools/test_config.properties")
        val to = File(copy, "app/src/test/resources/com/android/tools/test_config.properties")
        to.parentFile.mkdirs()
        assertTrue(from.renameTo(to))
    }

    @Test
    fun `no jsr305 strict`() = reports("fusion-core/build.gradle.kts: Maven compiles Kotlin with -Xjsr305=strict") {
        edit("fusion-core/build.gradle.kts", "        freeCompilerArgs.add(\"-Xjsr305=strict\")\n", "")
    }

    @Test
    fun `PublicApiTest without the class folder under Gradle`() = reports("Surefire's system property api.classes has no systemProperty") {
        edit("fusion-core/build.gradle.kts", "    systemProperty(\"api.classes\", sourceSets.main.get().output.classesDirs.asPath)\n", "")
    }

    @Test
    fun `PublicApiTest reading Maven's target folder`() = reports("PublicApiTest.kt reads \"target/classes\"") {
        edit("fusion-core/src/test/kotlin/dev/motionfusion/core/PublicApiTest.kt", "private val classes: File = PublicApi.classesOf(", "private val old = File(\"target/classes\")\n    private val classes: File = PublicApi.classesOf(")
    }

    @Test
    fun `a debug key other than Maven's`() = reports("the debug signingConfig's storeFile is null") {
        edit("app/build.gradle.kts", "            storeFile = file(\"debug.keystore\")\n", "")
    }

    @Test
    fun `no checksum for the distribution`() = reports("no distributionSha256Sum") {
        edit("gradle/wrapper/gradle-wrapper.properties", "distributionSha256Sum=", "#distributionSha256Sum=")
    }

    @Test
    fun `a gradlew bat handing PowerShell a program through cmd`() = reports("gradlew.bat:2: PowerShell is given its program on cmd's command line") {
        File(copy, "gradlew.bat").writeText("@echo off\r\npowershell -NoProfile -ExecutionPolicy Bypass -Command ^\r\n  \"\$ErrorActionPreference = Stop;\"\r\n")
    }

    @Test
    fun `no workflow for the Gradle build`() = reports(".github/workflows/gradle.yml is missing") { File(copy, ".github/workflows/gradle.yml").delete() }

    @Test
    fun `a version that drifts from the poms`() = reports("the Kotlin plugin is 2.4.20 in libs.versions.toml") {
        edit("gradle/libs.versions.toml", "kotlin = \"2.4.21\"", "kotlin = \"2.4.20\"")
    }

    @Test
    fun `an SDK level changed in the pom is asked of Gradle`() = reports("defaultConfig.targetSdk is 36, the Maven build says 37") {
        edit("app/pom.xml", "<android.targetSdk>36</android.targetSdk>", "<android.targetSdk>37</android.targetSdk>")
    }

    @Test
    fun `a dependency Gradle adds that Maven lacks`() = reports("build.gradle.kts has testImplementation junit:junit:4.13.2") {
        edit("fusion-cli/build.gradle.kts", "    testImplementation(libs.junit.jupiter)\n", "    testImplementation(libs.junit.jupiter)\n    testImplementation(libs.junit4)\n")
    }

    // --- the reader ---

    @Test
    fun `the reader gives calls, blocks, assignments and strings their structure`() {
        val nodes = KotlinDsl.parse(
            """
            tasks.withType<Test>().configureEach {
                maxHeapSize = "3g" // a comment
                jvmArgs("--add-opens", "java.base/java.io=ALL-UNNAMED")
                filesMatching("**/v.properties") { expand("project" to mapOf("version" to "${'$'}{x}")) }
            }
            """.trimIndent(),
            "t.kts",
        )
        val outer = nodes.single() as KotlinDsl.Call
        assertEquals("tasks.withType<Test>().configureEach", KotlinDsl.path(outer))
        val body = outer.lambda!!.body
        val assign = body[0] as KotlinDsl.Assign
        assertEquals("maxHeapSize", KotlinDsl.path(assign.target))
        assertEquals("3g", KotlinDsl.literal(assign.value))
        val jvm = body[1] as KotlinDsl.Call
        assertEquals(listOf("--add-opens", "java.base/java.io=ALL-UNNAMED"), jvm.args.map { KotlinDsl.literal(it.value) })
        val expand = (body[2] as KotlinDsl.Call).lambda!!.body.single() as KotlinDsl.Call
        val pair = expand.args.single().value as KotlinDsl.Binary
        assertEquals("to", pair.op)
        val template = (((pair.right as KotlinDsl.Call).args.single().value as KotlinDsl.Binary).right as KotlinDsl.Str)
        assertEquals(false, template.plain)
    }

    @Test
    fun `what the reader does not understand names file, line and column`() {
        val e = assertThrows(KotlinDsl.SyntaxError::class.java) { KotlinDsl.parse("android {\n    compileSdk = (34\n}\n", "app/build.gradle.kts") }
        assertTrue(e.message!!.startsWith("app/build.gradle.kts:3:1:"), e.message)
    }
}
