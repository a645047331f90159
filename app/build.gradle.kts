// The Android app (app/pom.xml). Android Studio builds it with the Android Gradle Plugin; the Maven
// build of record does the same steps with aapt2, D8/R8, zipalign and apksigner (tools/android-build.sh).
import com.android.build.api.artifact.SingleArtifact

plugins {
    alias(libs.plugins.android.application)
    alias(libs.plugins.kotlin.android)
}

android {
    namespace = "dev.motionfusion.app"
    compileSdk = 34

    defaultConfig {
        applicationId = "dev.motionfusion.app"
        minSdk = 26
        targetSdk = 36
        versionCode = 1
        versionName = "0.1.0"
    }

    sourceSets {
        getByName("main") {
            manifest.srcFile("src/main/AndroidManifest.xml")
            kotlin.srcDirs("src/main/kotlin")
            res.srcDirs("src/main/res")
        }
        getByName("test") {
            kotlin.srcDirs("src/test/kotlin")
            // Maven's filtered test_config.properties lives in src/test/maven-resources: AGP writes its own.
            resources.srcDirs("src/test/resources")
        }
    }

    // The committed key the Maven build signs debug APKs with, so either build installs over the other.
    signingConfigs {
        getByName("debug") {
            storeFile = file("debug.keystore")
            storePassword = "android"
            keyAlias = "androiddebugkey"
            keyPassword = "android"
            // The schemes tools/android-build.sh signs with (apksigner), written out rather than left to
            // either tool's defaults, which differ: APK Signature Scheme v2 and v3, no JAR signing
            // (minSdk 26 never needs it), no v4 file.
            enableV1Signing = false
            enableV2Signing = true
            enableV3Signing = true
            enableV4Signing = false
        }
    }

    buildTypes {
        getByName("debug") {
            signingConfig = signingConfigs.getByName("debug")
        }
        getByName("release") {
            isMinifyEnabled = true
            proguardFiles("proguard-rules.pro")
            // No signingConfig: a release build is signed with a key given to it, never the debug key.
        }
    }

    compileOptions {
        sourceCompatibility = JavaVersion.VERSION_17
        targetCompatibility = JavaVersion.VERSION_17
    }

    testOptions {
        // AGP then writes com/android/tools/test_config.properties (merged manifest, resources, package) for Robolectric.
        unitTests.isIncludeAndroidResources = true
    }
}

kotlin {
    jvmToolchain(17)
    compilerOptions {
        freeCompilerArgs.add("-Xjsr305=strict")
    }
}

// The API-level guard's signature file, for ApiLevelGuardTest (Maven: a test dependency of type signature).
val apiSignature by configurations.creating {
    isCanBeConsumed = false
    isTransitive = false
}
// Robolectric's runtime framework jars, API 26 to 35 (the SDK matrix), copied into a folder so the tests run offline (Maven: dependency:copy).
val robolectricRuntime by configurations.creating {
    isCanBeConsumed = false
    isTransitive = false
}

dependencies {
    implementation(project(":fusion-core"))
    implementation(project(":fusion-stream"))
    implementation(libs.kotlin.stdlib)
    implementation(libs.kotlinx.coroutines.android)
    implementation(libs.androidx.core.ktx)
    implementation(libs.androidx.appcompat)
    implementation(libs.androidx.activity.ktx)
    implementation(libs.androidx.lifecycle.runtime.ktx)
    implementation(libs.material)
    implementation(libs.zxing.core)

    testImplementation(libs.androidx.test.core)
    testImplementation(libs.androidx.test.ext.junit)
    testImplementation(libs.animal.sniffer)
    testImplementation(libs.android.manifest.merger)
    testImplementation(libs.robolectric)
    testImplementation(libs.junit4)
    testImplementation(platform(libs.junit.bom))
    testImplementation(libs.junit.vintage.engine)
    testImplementation(libs.junit.jupiter)
    testImplementation(libs.kotlinx.coroutines.test)
    testImplementation(libs.accessibility.test.framework)
    testRuntimeOnly(libs.junit.platform.launcher)

    apiSignature(variantOf(libs.gummy.bears.api26) { artifactType("signature") })
    robolectricRuntime(libs.android.all.instrumented.api26)
    robolectricRuntime(libs.android.all.instrumented.api27)
    robolectricRuntime(libs.android.all.instrumented.api28)
    robolectricRuntime(libs.android.all.instrumented.api29)
    robolectricRuntime(libs.android.all.instrumented.api30)
    robolectricRuntime(libs.android.all.instrumented.api31)
    robolectricRuntime(libs.android.all.instrumented.api32)
    robolectricRuntime(libs.android.all.instrumented.api33)
    robolectricRuntime(libs.android.all.instrumented.api34)
    robolectricRuntime(libs.android.all.instrumented.api35)
}

val robolectricDeps = tasks.register<Sync>("robolectricDeps") {
    from(robolectricRuntime)
    into(layout.buildDirectory.dir("robolectric-deps"))
}

/**
 * A test JVM's system property naming a file that a task or a configuration makes. The file is an
 * input of the test task by its content (not its absolute path, which only the argument holds), and
 * its producer runs first, so test results stay cacheable and relocatable.
 */
abstract class SystemPropertyFile : CommandLineArgumentProvider {
    @get:Input
    abstract val propertyName: Property<String>

    @get:InputFile
    @get:PathSensitive(PathSensitivity.NONE)
    abstract val file: RegularFileProperty

    override fun asArguments(): Iterable<String> = listOf("-D" + propertyName.get() + "=" + file.get().asFile.absolutePath)
}

/** As [SystemPropertyFile], for a folder: its files, by their paths inside it and their content. */
abstract class SystemPropertyDirectory : CommandLineArgumentProvider {
    @get:Input
    abstract val propertyName: Property<String>

    @get:InputDirectory
    @get:PathSensitive(PathSensitivity.RELATIVE)
    abstract val directory: DirectoryProperty

    override fun asArguments(): Iterable<String> = listOf("-D" + propertyName.get() + "=" + directory.get().asFile.absolutePath)
}

fun Test.systemPropertyFile(name: String, file: Provider<RegularFile>) {
    jvmArgumentProviders.add(objects.newInstance<SystemPropertyFile>().apply {
        propertyName.set(name)
        this.file.set(file)
    })
}

fun Test.systemPropertyDirectory(name: String, directory: Provider<Directory>) {
    jvmArgumentProviders.add(objects.newInstance<SystemPropertyDirectory>().apply {
        propertyName.set(name)
        this.directory.set(directory)
    })
}

// As Surefire in app/pom.xml: the same system properties, heap and JVM flags.
tasks.withType<Test>().configureEach {
    useJUnitPlatform()
    maxHeapSize = "3g"
    // java.io opened for Robolectric's ParcelFileDescriptor (ContentProvider.openFile, ContentResolver streams).
    jvmArgs("--add-opens", "java.base/java.io=ALL-UNNAMED")
    systemProperty("robolectric.offline", "true")
    systemPropertyDirectory("robolectric.dependency.dir", layout.dir(robolectricDeps.map { it.destinationDir }))
    systemProperty("robolectric.logging.enabled", "false")
    systemProperty("screenshots.dir", layout.buildDirectory.dir("screenshots").get().asFile.path)
    systemProperty("project.root", rootDir.path)
    systemPropertyFile("android.api.signature", layout.file(apiSignature.elements.map { it.single().asFile }))
    filter {
        // Tests of the Maven build's own machinery: the AndroidX lists of android-libs read from the local
        // Maven repository, the AARs android-libs unpacks, this mirror against the poms,
        // tools/android-build.sh (which needs Debian's zipalign and apksigner), AGP's merger run on
        // those AARs' manifests against the Maven build's manifest, and the Maven build's APKs.
        excludeTestsMatching("dev.motionfusion.app.build.LibraryTreeTest")
        excludeTestsMatching("dev.motionfusion.app.build.LibraryManifestsTest")
        excludeTestsMatching("dev.motionfusion.app.build.AndroidStudioProjectTest")
        excludeTestsMatching("dev.motionfusion.app.build.ReleaseSigningTest")
        excludeTestsMatching("dev.motionfusion.app.build.ManifestMergerTest")
        excludeTestsMatching("dev.motionfusion.app.build.MavenApkTest")
    }
}

// The merged manifest of each variant for its unit tests (Maven: the filtered manifest in target/manifest).
androidComponents {
    onVariants { variant ->
        val manifest = variant.artifacts.get(SingleArtifact.MERGED_MANIFEST)
        val testTask = "test" + variant.name.replaceFirstChar { it.uppercase() } + "UnitTest"
        tasks.withType<Test>().matching { it.name == testTask }.configureEach {
            systemPropertyFile("android.manifest", manifest)
        }
    }
}
